#include <new>

#include "hexapod_fw/firmware.hpp"
#include "hexapod_fw/hexapod_fw.h"

using hexapod_fw::Firmware;

namespace {
// The C hooks, adapted to the C++ ones (bool <-> uint8_t); kept beside the firmware object.
struct Instance {
  Firmware firmware;
  hx_hooks c_hooks;
};

void radio_write(void* ctx, const uint8_t* data, uint32_t n) {
  const hx_hooks& h = static_cast<Instance*>(ctx)->c_hooks;
  if (h.radio_write) h.radio_write(h.ctx, data, n);
}
void servo_write(void* ctx, const float* position, const float* velocity) {
  const hx_hooks& h = static_cast<Instance*>(ctx)->c_hooks;
  if (h.servo_write) h.servo_write(h.ctx, position, velocity);
}
bool servo_ping(void* ctx, uint8_t id) {
  const hx_hooks& h = static_cast<Instance*>(ctx)->c_hooks;
  return h.servo_ping ? h.servo_ping(h.ctx, id) != 0 : true;
}
void motor_power(void* ctx, bool on) {
  const hx_hooks& h = static_cast<Instance*>(ctx)->c_hooks;
  if (h.motor_power) h.motor_power(h.ctx, on ? 1 : 0);
}
void attitude(void* ctx, float* pitch, float* roll, float* yaw) {
  const hx_hooks& h = static_cast<Instance*>(ctx)->c_hooks;
  if (h.attitude) h.attitude(h.ctx, pitch, roll, yaw);
}

Instance* as_instance(void* fw) { return static_cast<Instance*>(fw); }
const Instance* as_instance(const void* fw) { return static_cast<const Instance*>(fw); }
}  // namespace

extern "C" {

size_t hx_size(void) { return sizeof(Instance); }

int hx_init(void* mem, size_t size, const hx_hooks* hooks, uint32_t walk_duration_ms,
            uint16_t failsafe_windows, uint16_t telemetry_ticks, uint16_t ping_check_ticks,
            const uint8_t* leg_map, uint32_t now_ms) {
  hexapod_fw::LegMount mounts[hexapod_fw::kLegs];
  if (mem == nullptr || size < sizeof(Instance) ||
      reinterpret_cast<uintptr_t>(mem) % alignof(Instance) != 0 || hooks == nullptr ||
      failsafe_windows == 0 || telemetry_ticks == 0 || ping_check_ticks == 0 ||
      (leg_map != nullptr && !hexapod_fw::slot_mounts(leg_map, mounts))) {
    return -1;
  }
  Instance* instance = new (mem) Instance();
  instance->c_hooks = *hooks;
  hexapod_fw::Hooks h = {instance, radio_write, servo_write, servo_ping, motor_power,
                         hooks->attitude ? attitude : nullptr};
  hexapod_fw::Config config;
  config.walk_duration_ms = walk_duration_ms;
  config.failsafe_windows = failsafe_windows;
  config.telemetry_ticks = telemetry_ticks;
  config.ping_check_ticks = ping_check_ticks;
  if (leg_map != nullptr) {
    for (int k = 0; k < hexapod_fw::kLegs; ++k) config.leg_map[k] = leg_map[k];
  }
  instance->firmware.begin(h, config, now_ms);
  return 0;
}

void hx_receive(void* fw, const uint8_t* data, size_t n, uint32_t now_ms) {
  for (size_t i = 0; i < n; ++i) as_instance(fw)->firmware.on_byte(data[i], now_ms);
}

void hx_poll(void* fw, uint32_t now_ms) { as_instance(fw)->firmware.poll(now_ms); }

void hx_get_state(const void* fw, hx_state* out) {
  const Firmware& f = as_instance(fw)->firmware;
  const hexapod_fw::State s = f.state();
  *out = hx_state{};
  out->walking = s.walking;
  out->estopped = s.estopped;
  out->motors_on = s.motors_on;
  out->trial_state = s.trial_state;
  out->trial_seq = s.trial_seq;
  out->staged = s.staged;
  out->gait_id = s.gait_id;
  out->table_rows = s.table_rows;
  out->tick_count = s.tick_count;
  out->walk_start_ms = s.walk_start_ms;
  out->walk_end_ms = s.walk_end_ms;
  out->frames = f.stats().frames;
  out->pings = f.stats().pings;
  out->duplicates = f.stats().duplicates;
  out->failsafe_trips = f.stats().failsafe_trips;
  out->missed_windows = f.stats().missed_windows;
  out->checksum_errors = f.receiver_stats().checksum_errors;
  out->resyncs = f.receiver_stats().resyncs;
  out->bytes_dropped = f.receiver_stats().bytes_dropped;
}

void hx_gait(const void* fw, double* values) {
  const double* g = as_instance(fw)->firmware.gait();
  for (int i = 0; i < hexapod_fw::kParams; ++i) values[i] = g[i];
}

int hx_table_row(const void* fw, int row, float* position, float* velocity) {
  const hexapod_fw::GaitTable& t = as_instance(fw)->firmware.table();
  if (row < 0 || row >= t.rows) return 0;
  for (int j = 0; j < hexapod_fw::kJoints; ++j) {
    position[j] = t.position_rad(row, j);
    velocity[j] = t.velocity_rad_s(row, j);
  }
  return 1;
}

}  // extern "C"
