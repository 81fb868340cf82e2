// The module linked as the robot's firmware links it: one static instance, no heap, hooks that do
// nothing. Built for the size report (make -C firmware arm) and, run on QEMU's Cortex-M4 board,
// for instruction counts (make -C firmware arm-counts): PROBE_SCENARIO picks what it does.
#include <stdint.h>

#include "hexapod_fw/crc16.hpp"
#include "hexapod_fw/firmware.hpp"

#ifndef PROBE_SCENARIO
#define PROBE_SCENARIO 0
#endif

using namespace hexapod_fw;

extern "C" {
extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();
void Reset_Handler();
}

namespace {
Firmware g_firmware;  // the firmware's one instance: static storage

void radio_write(void*, const uint8_t*, uint32_t) {}
void servo_write(void*, const float*, const float*) {}
bool servo_ping(void*, uint8_t) { return true; }
void motor_power(void*, bool) {}

uint8_t g_seq = 0;
uint32_t g_now = 0;

void feed(const uint8_t* frame) {
  for (int i = 0; i < kFrameLen; ++i) g_firmware.on_byte(frame[i], g_now);
}

void command(uint8_t type, const uint8_t payload[5]) {
  uint8_t frame[kFrameLen] = {kMarker, type, ++g_seq};
  for (int i = 0; i < 5; ++i) frame[3 + i] = payload[i];
  const uint16_t crc = crc16(frame, 8);
  frame[8] = static_cast<uint8_t>(crc >> 8);
  frame[9] = static_cast<uint8_t>(crc);
  feed(frame);
}

void put_f32(float value, uint8_t* p) {
  uint32_t bits;
  __builtin_memcpy(&bits, &value, 4);
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(bits >> (8 * i));
}

uint16_t set_params(const double* values) {
  uint16_t crc = 0xFFFF;
  for (int i = 0; i < kParams; ++i) {
    uint8_t payload[5] = {static_cast<uint8_t>(i)};
    put_f32(static_cast<float>(values[i]), payload + 1);
    command(kCmdSetParam, payload);
    crc = crc16(payload + 1, 4, crc);
  }
  return crc;
}

void commit(uint16_t crc) {
  const uint8_t payload[5] = {kParams, static_cast<uint8_t>(crc >> 8),
                              static_cast<uint8_t>(crc), 0, 9};
  command(kCmdCommit, payload);
}

void scenario() {
  Hooks hooks = {nullptr, radio_write, servo_write, servo_ping, motor_power, nullptr};
  g_firmware.begin(hooks, Config(), g_now);
  double slow[kParams];  // the tripod at a 10 s period (1200 rows), slow enough to reach
  for (int i = 0; i < kParams; ++i) slow[i] = kDefaultGait[i];
  slow[kPeriod] = 10.0;
  slow[kBodyVelocity] = 0.02;
  const uint8_t payload[5] = {0, 0, 0, 0, 0};
  switch (PROBE_SCENARIO) {
    case 1:  // fill the ACK memory (65 commands)
    case 2:  // ... and one more frame
      for (int i = 0; i < (PROBE_SCENARIO == 2 ? 66 : 65); ++i) command(kCmdSetParam, payload);
      break;
    case 3:  // upload and commit the 1 s tripod (120 rows)
      commit(set_params(kDefaultGait));
      break;
    case 4:  // the 10 s gait's upload without its commit
      set_params(slow);
      break;
    case 5:  // upload and commit the 10 s gait (1200 rows)
      commit(set_params(slow));
      break;
    default:  // start-up only
      break;
  }
  g_now += 1;
  g_firmware.poll(g_now);
}

[[noreturn]] void semihosting_exit() {
  // SYS_EXIT (0x18) with ADP_Stopped_ApplicationExit: QEMU ends; on a board, a breakpoint
  register uint32_t r0 __asm__("r0") = 0x18;
  register uint32_t r1 __asm__("r1") = 0x20026;
  __asm__ volatile("bkpt 0xAB" : : "r"(r0), "r"(r1) : "memory");
  for (;;) {
  }
}
}  // namespace

extern "C" void Reset_Handler() {
  for (uint32_t *src = &_sidata, *dst = &_sdata; dst < &_edata;) *dst++ = *src++;
  for (uint32_t* dst = &_sbss; dst < &_ebss;) *dst++ = 0;
  // the FPU (CP10, CP11) on: the module is built for hard float
  volatile uint32_t* cpacr = reinterpret_cast<volatile uint32_t*>(0xE000ED88);
  *cpacr |= (0xFu << 20);
  __asm__ volatile("dsb\n isb");
  for (void (**init)() = __init_array_start; init < __init_array_end; ++init) (*init)();
  scenario();
  semihosting_exit();
}

// Only the reset vector: the probe takes no interrupts.
__attribute__((section(".isr_vector"), used)) const void* const g_vectors[2] = {
    &_estack, reinterpret_cast<const void*>(&Reset_Handler)};
