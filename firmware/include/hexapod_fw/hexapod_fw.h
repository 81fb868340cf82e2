/* C interface of the firmware module, for hosts that load it as a shared library (the robot
 * emulator's --firmware native, through Python's ctypes) and for C firmware. The caller owns the
 * memory: hx_size() bytes aligned to 8, so the module itself never allocates. */
#ifndef HEXAPOD_FW_H
#define HEXAPOD_FW_H
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hx_hooks {
  void* ctx;
  void (*radio_write)(void* ctx, const uint8_t* data, uint32_t n);
  void (*servo_write)(void* ctx, const float* position, const float* velocity);
  uint8_t (*servo_ping)(void* ctx, uint8_t servo_id); /* 1 if it answered */
  void (*motor_power)(void* ctx, uint8_t on);
  void (*attitude)(void* ctx, float* pitch, float* roll, float* yaw); /* may be NULL */
} hx_hooks;

typedef struct hx_state {
  uint8_t walking, estopped, motors_on, trial_state, trial_seq, staged;
  uint16_t gait_id, table_rows;
  uint32_t tick_count, walk_start_ms, walk_end_ms;
  uint32_t frames, pings, duplicates, failsafe_trips, missed_windows;
  uint32_t checksum_errors, resyncs, bytes_dropped;
} hx_state;

size_t hx_size(void);
/* 0 on success, -1 if the memory is too small or misaligned, or the configuration is bad.
 * leg_map: the robot's leg number of each of the six URDF legs (bridge_node's leg_map), a
 * permutation of 1..6; NULL for identity. */
int hx_init(void* mem, size_t size, const hx_hooks* hooks, uint32_t walk_duration_ms,
            uint16_t failsafe_windows, uint16_t telemetry_ticks, uint16_t ping_check_ticks,
            const uint8_t* leg_map, uint32_t now_ms);
void hx_receive(void* fw, const uint8_t* data, size_t n, uint32_t now_ms);
void hx_poll(void* fw, uint32_t now_ms);
void hx_get_state(const void* fw, hx_state* out);
/* The gait in use: 36 values in the protocol's parameter order. */
void hx_gait(const void* fw, double* values);
/* Row ``row`` of the 120 Hz table: 18 positions [rad] and 18 rates [rad/s]; 0 if no such row. */
int hx_table_row(const void* fw, int row, float* position, float* velocity);

#ifdef __cplusplus
}
#endif
#endif
