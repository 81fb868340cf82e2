// Replays a recorded input script through the firmware module and prints what it sends and its
// state after every event: the C++ side of the differential tests (tests/test_firmware_native.py
// runs the same script through the Python model). Built with -fsanitize=address,undefined.
//
// Script (stdin, little-endian):
//   'H' u32 walk_ms u16 failsafe_windows u16 telemetry_ticks u16 ping_check_ticks u32 now_ms
//       u32 dead_servo_mask (bit i: servo id i does not answer)
//       u8[6] leg_map (the robot's leg number of each URDF leg)         -- once, first
//   'B' u32 now_ms u16 n, n bytes                                      -- radio bytes arrive
//   'P' u32 now_ms                                                     -- the main loop polls
//   'T'                                                                -- print the gait table
//   'S'                                                                -- print the servo targets
// Output: one line per B/P event, "E <radio bytes in hex or -> <walking> <estopped> <motors_on>
// <gait_id> <staged> <tick_count> <trial_state> <table_rows>"; "G <36 values>" when the gait
// changed; for T, "T <rows>" and one line per row of 18 positions and 18 rates; for S,
// "S <writes> <18 positions>": the number of servo writes so far and the last targets.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <vector>

#include "hexapod_fw/hexapod_fw.h"

namespace {
struct Host {
  std::vector<uint8_t> radio;
  uint32_t dead_mask = 0;
  float position[18] = {};
  uint32_t writes = 0;
};

void radio_write(void* ctx, const uint8_t* data, uint32_t n) {
  Host* host = static_cast<Host*>(ctx);
  host->radio.insert(host->radio.end(), data, data + n);
}
void servo_write(void* ctx, const float* position, const float*) {
  Host* host = static_cast<Host*>(ctx);
  memcpy(host->position, position, sizeof host->position);
  ++host->writes;
}
uint8_t servo_ping(void* ctx, uint8_t id) {
  return (static_cast<Host*>(ctx)->dead_mask >> id) & 1u ? 0 : 1;
}
void motor_power(void*, uint8_t) {}

bool read_exact(void* out, size_t n) { return fread(out, 1, n, stdin) == n; }
template <typename T>
bool read_value(T* out) {
  return read_exact(out, sizeof *out);
}

[[noreturn]] void fail(const char* what) {
  fprintf(stderr, "replay: %s\n", what);
  exit(2);
}
}  // namespace

int main() {
  Host host;
  hx_hooks hooks = {&host, radio_write, servo_write, servo_ping, motor_power, nullptr};
  char tag;
  uint32_t walk_ms, now_ms;
  uint16_t failsafe, telemetry, ping_check;
  uint8_t leg_map[6];
  if (!read_value(&tag) || tag != 'H' || !read_value(&walk_ms) || !read_value(&failsafe) ||
      !read_value(&telemetry) || !read_value(&ping_check) || !read_value(&now_ms) ||
      !read_value(&host.dead_mask) || !read_exact(leg_map, sizeof leg_map)) {
    fail("the script must start with an H record");
  }
  std::vector<uint64_t> memory((hx_size() + 7) / 8);
  void* fw = memory.data();
  if (hx_init(fw, memory.size() * 8, &hooks, walk_ms, failsafe, telemetry, ping_check, leg_map,
              now_ms)) {
    fail("hx_init refused the configuration");
  }
  double gait[36], last[36];
  hx_gait(fw, last);
  std::vector<uint8_t> bytes;
  while (read_value(&tag)) {
    if (tag == 'T') {
      hx_state s;
      hx_get_state(fw, &s);
      printf("T %u\n", s.table_rows);
      float p[18], v[18];
      for (int row = 0; hx_table_row(fw, row, p, v); ++row) {
        for (int j = 0; j < 18; ++j) printf("%.9g ", p[j]);
        for (int j = 0; j < 18; ++j) printf("%.9g%c", v[j], j == 17 ? '\n' : ' ');
      }
      continue;
    }
    if (tag == 'S') {
      printf("S %u", host.writes);
      for (float p : host.position) printf(" %.9g", p);
      printf("\n");
      continue;
    }
    if (!read_value(&now_ms)) fail("truncated record");
    if (tag == 'B') {
      uint16_t n;
      if (!read_value(&n)) fail("truncated B record");
      bytes.resize(n);
      if (n && !read_exact(bytes.data(), n)) fail("truncated B record");
      hx_receive(fw, bytes.data(), n, now_ms);
    } else if (tag == 'P') {
      hx_poll(fw, now_ms);
    } else {
      fail("unknown record");
    }
    hx_state s;
    hx_get_state(fw, &s);
    printf("E ");
    if (host.radio.empty()) printf("-");
    for (uint8_t b : host.radio) printf("%02x", b);
    host.radio.clear();
    printf(" %u %u %u %u %u %u %u %u\n", s.walking, s.estopped, s.motors_on, s.gait_id, s.staged,
           s.tick_count, s.trial_state, s.table_rows);
    hx_gait(fw, gait);
    if (memcmp(gait, last, sizeof gait) != 0) {
      printf("G");
      for (double g : gait) printf(" %.17g", g);
      printf("\n");
      memcpy(last, gait, sizeof gait);
    }
  }
  return 0;
}
