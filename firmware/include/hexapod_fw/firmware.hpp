// The robot side of the radio protocol: legacy frames, extension v1 (gait upload, trials,
// emergency stop), the gait table, the trial state machine and the servo health check.
//
// No HAL, no heap: the integrator gives the hooks and calls on_byte() for every received radio
// byte and poll() from the main loop (firmware/INTEGRATION.md). Time is the caller's millisecond
// clock (HAL_GetTick), compared wrap-safe. The behaviour is specified by the Python model
// hexapod_bridge/emulator/firmware.py; the differential tests hold the two to the same bytes.
#pragma once
#include <stdint.h>

#include "hexapod_fw/gait.hpp"
#include "hexapod_fw/generated.hpp"
#include "hexapod_fw/receiver.hpp"

namespace hexapod_fw {

struct Hooks {
  void* ctx;
  // Send bytes on the radio (a whole frame per call).
  void (*radio_write)(void* ctx, const uint8_t* data, uint32_t n);
  // New joint targets [rad] and rates [rad/s], 18 joints: the robot's legs 1..6 (its slots of
  // the per-leg parameters), each coxa, femur, tibia. Called at most at 120 Hz.
  void (*servo_write)(void* ctx, const float* position, const float* velocity);
  // Ping one Dynamixel (ids kFirstServo..kLastServo); true if it answered. Never called while
  // walking.
  bool (*servo_ping)(void* ctx, uint8_t servo_id);
  // Switch the servos' power (legacy FF FA, ESTOP).
  void (*motor_power)(void* ctx, bool on);
  // Optional: the body attitude for telemetry [rad]; nullptr sends zeros.
  void (*attitude)(void* ctx, float* pitch, float* roll, float* yaw);
};

struct Config {
  uint32_t walk_duration_ms = kWalkDurationMs;  // a walk after a reset (movement function 55)
  uint16_t failsafe_windows = kFailsafeWindows;
  uint16_t telemetry_ticks = kTelemetryTicks;
  uint16_t ping_check_ticks = kPingCheckTicks;
  // The robot's leg number (its slot of the per-leg parameters and servos) of each URDF leg:
  // bridge_node's leg_map, which must be the same. Identity by default; a value that is not a
  // permutation of 1..6 is taken as identity (hx_init refuses it).
  uint8_t leg_map[kLegs] = {1, 2, 3, 4, 5, 6};
};

struct Stats {
  uint32_t pings;
  uint32_t failsafe_trips;
  uint32_t missed_windows;
  uint32_t frames;
  uint32_t duplicates;
};

// What a caller may read between calls (tests, the emulator, a status LED).
struct State {
  bool walking;
  bool estopped;
  bool motors_on;
  uint8_t trial_state;  // TrialState of the last report
  uint8_t trial_seq;
  uint8_t staged;       // parameters staged since the last commit
  uint16_t gait_id;
  uint16_t table_rows;
  uint32_t tick_count;
  uint32_t walk_start_ms;
  uint32_t walk_end_ms;
};

class Firmware {
 public:
  void begin(const Hooks& hooks, const Config& config, uint32_t now_ms);
  // One received radio byte at time now_ms.
  void on_byte(uint8_t byte, uint32_t now_ms);
  // Timers, the walk, servo targets and the health check up to now_ms.
  void poll(uint32_t now_ms);

  State state() const;
  const Stats& stats() const { return stats_; }
  const ReceiverStats& receiver_stats() const { return receiver_.stats(); }
  const GaitTable& table() const { return table_; }
  const double* gait() const { return gait_; }

 private:
  void on_frame(FrameKind kind, const uint8_t* f);
  void on_movement(const uint8_t* f);
  void on_legacy_command(const uint8_t* f);
  void on_extension(const uint8_t* f);
  void ack(uint8_t type, uint8_t seq, uint8_t status, uint16_t value);
  void report(uint8_t type, uint8_t seq, const uint8_t payload[4]);
  void text(const char* message);
  void send(const uint8_t* data, uint32_t n);
  bool load_gait(const double* values, BuildResult* result);
  void start_walk(uint32_t duration_ms);
  void stop_walk(uint8_t state);
  void trial_report(uint8_t state, uint32_t at_ms);
  void timer_tick();
  void health_check();
  void write_targets();
  void write(const float* velocity);  // fold, then the servo hook
  void begin_transition();
  void set_motors(bool on);

  // Every member starts as zero, so a static instance lives in .bss (no flash image of it);
  // begin() sets the real values.
  Hooks hooks_ = {};
  uint32_t walk_duration_ms_ = 0;
  uint16_t failsafe_windows_ = 0;
  uint16_t ping_check_ticks_ = 0;
  Receiver receiver_;
  Stats stats_ = {};
  uint32_t now_ms_ = 0;

  // gaits: the one in use and its table; staged SET_PARAM values (float32, as sent)
  LegMount mounts_[kLegs] = {};  // each slot's leg mount (slot_mounts of Config::leg_map)
  double gait_[kParams] = {};
  uint16_t gait_id_ = 0;
  GaitTable table_ = {};
  float staged_[kParams] = {};
  uint64_t staged_mask_ = 0;

  // the last 64 acknowledged (type, seq) pairs and their ACK frames, oldest first from head
  static constexpr int kAckMemory = 64;
  uint8_t ack_key_[kAckMemory][2] = {};
  uint8_t ack_frame_[kAckMemory][kFrameLen] = {};
  uint8_t ack_head_ = 0;
  uint8_t ack_count_ = 0;

  // walking and standing
  bool walking_ = false;
  bool estopped_ = false;
  bool motors_on_ = false;
  uint8_t trial_state_ = kTrialIdle;
  uint8_t trial_seq_ = 0;
  uint32_t walk_start_ms_ = 0;
  uint32_t walk_end_ms_ = 0;
  int32_t last_row_ = 0;  // the walk's last written row (counted from its start; -1: none)
  float pose_[kJoints] = {};             // the targets last written
  float transition_from_[kJoints] = {};  // standing: from here to the table's first row
  bool transition_ = false;
  bool transition_pending_ = false;
  uint32_t transition_start_ms_ = 0;
  int32_t transition_step_ = 0;

  // timer tick, keep-alive, telemetry, health check
  uint32_t tick_count_ = 0;
  uint32_t next_tick_ms_ = 0;
  uint16_t telemetry_ticks_ = 0;
  uint32_t pings_in_window_ = 0;
  uint32_t missed_ = 0;
  bool health_pending_ = false;
  uint32_t dead_mask_ = 0;  // bit i: servo id i did not answer the last health check
};

}  // namespace hexapod_fw
