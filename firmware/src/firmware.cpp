#include "hexapod_fw/firmware.hpp"

#include <math.h>
#include <string.h>

#include "hexapod_fw/crc16.hpp"

namespace hexapod_fw {

namespace {
constexpr uint8_t kFrameAck = 0xFF;  // robot -> PC frames start with FF
constexpr uint8_t kPingReply[2] = {0xFF, 0xFA};
constexpr uint32_t kRateHz = static_cast<uint32_t>(kRobotRate);

// a - b on a wrapping millisecond clock, as a signed difference
int32_t since(uint32_t a, uint32_t b) { return static_cast<int32_t>(a - b); }

float read_f32_le(const uint8_t* p) {
  uint32_t bits = static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
                  (static_cast<uint32_t>(p[2]) << 16) | (static_cast<uint32_t>(p[3]) << 24);
  float value;
  memcpy(&value, &bits, sizeof value);
  return value;
}

void write_f32_le(float value, uint8_t* p) {
  uint32_t bits;
  memcpy(&bits, &value, sizeof bits);
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(bits >> (8 * i));
}

uint16_t read_u16_be(const uint8_t* p) { return static_cast<uint16_t>((p[0] << 8) | p[1]); }
}  // namespace

void Firmware::begin(const Hooks& hooks, const Config& config, uint32_t now_ms) {
  hooks_ = hooks;
  walk_duration_ms_ = config.walk_duration_ms;
  failsafe_windows_ = config.failsafe_windows;
  ping_check_ticks_ = config.ping_check_ticks;
  motors_on_ = true;
  last_row_ = -1;
  now_ms_ = now_ms;
  next_tick_ms_ = now_ms;
  telemetry_ticks_ = config.telemetry_ticks;
  static const uint8_t kIdentity[kLegs] = {1, 2, 3, 4, 5, 6};
  const uint8_t* leg_map = config.leg_map;
  if (!slot_mounts(leg_map, mounts_)) {
    leg_map = kIdentity;
    slot_mounts(leg_map, mounts_);
  }
  // the compiled-in tripod (URDF leg order) in the robot's slots
  for (int i = 0; i < kParams; ++i) gait_[i] = kDefaultGait[i];
  for (int k = 0; k < kLegs; ++k) {
    for (int field = kRadius; field <= kPhaseOffset; field += kLegs) {
      gait_[field + leg_map[k] - 1] = kDefaultGait[field + k];
    }
  }
  gait_id_ = 0;
  build_table(gait_, mounts_, table_);  // the compiled-in tripod is reachable (a test checks it)
  float zero[kJoints] = {};
  for (int j = 0; j < kJoints; ++j) pose_[j] = table_.position_rad(0, j);
  dead_mask_ = 0;
  if (hooks_.servo_write) write(zero);
  health_pending_ = true;
}

State Firmware::state() const {
  State s = {};
  s.walking = walking_;
  s.estopped = estopped_;
  s.motors_on = motors_on_;
  s.trial_state = trial_state_;
  s.trial_seq = trial_seq_;
  uint8_t staged = 0;
  for (int i = 0; i < kParams; ++i) staged = static_cast<uint8_t>(staged + ((staged_mask_ >> i) & 1u));
  s.staged = staged;
  s.gait_id = gait_id_;
  s.table_rows = table_.rows;
  s.tick_count = tick_count_;
  s.walk_start_ms = walk_start_ms_;
  s.walk_end_ms = walk_end_ms_;
  return s;
}

// ---- receiving ------------------------------------------------------------------------------
void Firmware::on_byte(uint8_t byte, uint32_t now_ms) {
  now_ms_ = now_ms;
  FrameKind kind = receiver_.push(byte);
  if (kind != FrameKind::kNone) on_frame(kind, receiver_.frame());
}

void Firmware::on_frame(FrameKind kind, const uint8_t* f) {
  ++stats_.frames;
  switch (kind) {
    case FrameKind::kPing:
      ++stats_.pings;
      ++pings_in_window_;
      send(kPingReply, 2);
      break;
    case FrameKind::kMovement: {
      const uint8_t ack_frame[2] = {kFrameAck, f[9]};
      send(ack_frame, 2);
      on_movement(f);
      break;
    }
    case FrameKind::kLegacyCommand:
      on_legacy_command(f);
      break;
    case FrameKind::kExtension:
      on_extension(f);
      break;
    case FrameKind::kNone:
      break;
  }
}

void Firmware::on_movement(const uint8_t* f) {
  const uint8_t direction = f[1], function = f[8];
  if (function == kFunctionReset) {
    text("RESET");
    start_walk(walk_duration_ms_);
  } else if (function == kFunctionStand || direction == 0) {
    stop_walk(kTrialStopped);
  } else if (function == kFunctionWalk) {  // direction is 1..8 (the receiver checked it)
    double values[kParams];
    for (int i = 0; i < kParams; ++i) values[i] = gait_[i];
    values[kBodyVelocity] = f[4] / 100.0;
    values[kBodyHeight] = (280.0 * f[6]) / 100.0 / 1000.0;
    values[kCrabAngle] = kDirectionAngle[direction];
    const Range& v = kParamRanges[kBodyVelocity];
    const Range& h = kParamRanges[kBodyHeight];
    BuildResult result;
    if (!(values[kBodyVelocity] >= v.lo && values[kBodyVelocity] <= v.hi &&
          values[kBodyHeight] >= h.lo && values[kBodyHeight] <= h.hi) ||
        !load_gait(values, &result)) {
      text("BAD MOVEMENT");  // the gait is kept
    }
  }
}

void Firmware::on_legacy_command(const uint8_t* f) {
  if (f[1] == 0xDD) {  // telemetry period [s]
    const double period = read_f32_le(f + 2);
    if (isfinite(period) && period >= 0.05 && period <= 60.0) {
      const double ticks = nearbyint(period / (kTickMs / 1000.0));
      telemetry_ticks_ = static_cast<uint16_t>(ticks < 1.0 ? 1.0 : ticks);
    }
  }
  if (f[1] == 0xFA) {  // motor power
    set_motors(f[2] != 0);
    if (motors_on_) {
      estopped_ = false;
    } else {
      stop_walk(kTrialStopped);
    }
  }
}

void Firmware::on_extension(const uint8_t* f) {
  const uint8_t type = f[1], seq = f[2];
  const uint8_t* p = f + 3;
  if (type != kCmdEstop) {  // a retransmission: answer again, apply once
    for (int i = 0; i < ack_count_; ++i) {
      const int slot = (ack_head_ + i) % kAckMemory;
      if (ack_key_[slot][0] == type && ack_key_[slot][1] == seq) {
        ++stats_.duplicates;
        send(ack_frame_[slot], kFrameLen);
        return;
      }
    }
  }
  switch (type) {
    case kCmdSetParam: {
      const uint8_t index = p[0];
      if (index >= kParams) return ack(type, seq, kStatusBadIndex, index);
      const float value = read_f32_le(p + 1);
      const double v = value;
      if (!(isfinite(v) && kParamRanges[index].lo <= v && v <= kParamRanges[index].hi)) {
        return ack(type, seq, kStatusOutOfRange, index);
      }
      staged_[index] = value;
      staged_mask_ |= (uint64_t{1} << index);
      return ack(type, seq, kStatusOk, index);
    }
    case kCmdCommit: {
      const uint8_t count = p[0];
      const uint16_t set_crc = read_u16_be(p + 1), gait_id = read_u16_be(p + 3);
      const uint64_t all = (uint64_t{1} << kParams) - 1;
      if (count != kParams || staged_mask_ != all) {
        return ack(type, seq, kStatusSetIncomplete, gait_id);
      }
      uint16_t crc = 0xFFFF;
      for (int i = 0; i < kParams; ++i) {
        uint8_t bytes[4];
        write_f32_le(staged_[i], bytes);
        crc = crc16(bytes, 4, crc);
      }
      if (crc != set_crc) return ack(type, seq, kStatusSetCrcMismatch, gait_id);
      if (walking_) return ack(type, seq, kStatusBusy, gait_id);
      double values[kParams];
      for (int i = 0; i < kParams; ++i) values[i] = staged_[i];
      values[kArchiveIndex] = trunc(values[kArchiveIndex]);  // a whole number, as hexapod_gait
      BuildResult result;
      if (!load_gait(values, &result)) {
        text("GAIT REJECTED");
        return ack(type, seq,
                   result == BuildResult::kUnreachable ? kStatusUnreachable : kStatusOutOfRange,
                   gait_id);
      }
      gait_id_ = gait_id;
      staged_mask_ = 0;
      return ack(type, seq, kStatusOk, gait_id);
    }
    case kCmdStartTrial: {
      const uint16_t ms = read_u16_be(p), gait_id = read_u16_be(p + 2);
      if (estopped_ || !motors_on_) return ack(type, seq, kStatusEstopped, gait_id);
      if (gait_id != gait_id_) return ack(type, seq, kStatusNoGait, gait_id);
      if (walking_) return ack(type, seq, kStatusBusy, gait_id);
      ack(type, seq, kStatusOk, gait_id);
      start_walk(ms);
      return;
    }
    case kCmdStopTrial:
      ack(type, seq, kStatusOk, 0);
      stop_walk(kTrialStopped);
      return;
    case kCmdEstop:
      estopped_ = true;
      set_motors(false);
      stop_walk(kTrialEstopped);
      ack(type, seq, kStatusOk, 0);
      return;
    case kCmdHello: {
      const uint8_t payload[4] = {kProtocolMajor, kProtocolMinor,
                                  static_cast<uint8_t>(kCapabilities >> 8),
                                  static_cast<uint8_t>(kCapabilities & 0xFF)};
      report(kReportVersion, seq, payload);
      health_pending_ = true;  // a host that says hello hears of every dead servo
      return;
    }
    default:
      ack(type, seq, kStatusUnknownType, 0);
      return;
  }
}

// Build the table of ``values``; on failure rebuild the gait in use (the last good state).
bool Firmware::load_gait(const double* values, BuildResult* result) {
  *result = build_table(values, mounts_, table_);
  if (*result != BuildResult::kOk) {
    build_table(gait_, mounts_, table_);
    return false;
  }
  for (int i = 0; i < kParams; ++i) gait_[i] = values[i];
  if (!walking_) transition_pending_ = true;  // standing: move to the new first pose
  return true;
}

// ---- sending --------------------------------------------------------------------------------
void Firmware::send(const uint8_t* data, uint32_t n) {
  if (hooks_.radio_write) hooks_.radio_write(hooks_.ctx, data, n);
}

void Firmware::report(uint8_t type, uint8_t seq, const uint8_t payload[4]) {
  uint8_t frame[kFrameLen] = {kFrameAck, kMarker, type, seq,
                              payload[0], payload[1], payload[2], payload[3]};
  const uint16_t crc = crc16(frame, 8);
  frame[8] = static_cast<uint8_t>(crc >> 8);
  frame[9] = static_cast<uint8_t>(crc & 0xFF);
  send(frame, kFrameLen);
}

void Firmware::ack(uint8_t type, uint8_t seq, uint8_t status, uint16_t value) {
  uint8_t frame[kFrameLen] = {kFrameAck, kMarker, kReportAck, seq, type, status,
                              static_cast<uint8_t>(value >> 8),
                              static_cast<uint8_t>(value & 0xFF)};
  const uint16_t crc = crc16(frame, 8);
  frame[8] = static_cast<uint8_t>(crc >> 8);
  frame[9] = static_cast<uint8_t>(crc & 0xFF);
  int slot = -1;
  for (int i = 0; i < ack_count_ && slot < 0; ++i) {
    const int s = (ack_head_ + i) % kAckMemory;
    if (ack_key_[s][0] == type && ack_key_[s][1] == seq) slot = s;  // answered again (ESTOP)
  }
  if (slot < 0) {
    if (ack_count_ < kAckMemory) {
      slot = (ack_head_ + ack_count_) % kAckMemory;
      ++ack_count_;
    } else {  // forget the oldest
      slot = ack_head_;
      ack_head_ = static_cast<uint8_t>((ack_head_ + 1) % kAckMemory);
    }
    ack_key_[slot][0] = type;
    ack_key_[slot][1] = seq;
  }
  memcpy(ack_frame_[slot], frame, kFrameLen);
  send(frame, kFrameLen);
}

void Firmware::text(const char* message) {
  constexpr uint32_t kMaxText = 32;  // the module's messages are short ("GAIT REJECTED")
  uint8_t frame[3 + kMaxText] = {0xFF, 0xFC, 0};
  uint32_t n = static_cast<uint32_t>(strlen(message));
  if (n > kMaxText) n = kMaxText;
  frame[2] = static_cast<uint8_t>(n);
  memcpy(frame + 3, message, n);
  send(frame, 3 + n);
}

// ---- walking --------------------------------------------------------------------------------
void Firmware::start_walk(uint32_t duration_ms) {
  walking_ = true;
  walk_start_ms_ = now_ms_;
  walk_end_ms_ = now_ms_ + duration_ms;
  last_row_ = -1;
  transition_ = transition_pending_ = false;
  trial_report(kTrialWalking, walk_start_ms_);
}

void Firmware::stop_walk(uint8_t state) {
  if (!walking_) return;
  walking_ = false;
  health_pending_ = true;  // the legs stand still again: check the servos
  trial_report(state, state == kTrialDone ? walk_end_ms_ : now_ms_);
}

void Firmware::trial_report(uint8_t state, uint32_t at_ms) {
  int32_t elapsed = since(at_ms, walk_start_ms_);
  if (elapsed < 0) elapsed = 0;
  if (elapsed > 0xFFFFFF) elapsed = 0xFFFFFF;
  trial_state_ = state;
  trial_seq_ = static_cast<uint8_t>(trial_seq_ + 1);
  const uint8_t payload[4] = {state, static_cast<uint8_t>(elapsed >> 16),
                              static_cast<uint8_t>(elapsed >> 8),
                              static_cast<uint8_t>(elapsed)};
  report(kReportTrial, trial_seq_, payload);
}

void Firmware::set_motors(bool on) {
  motors_on_ = on;
  if (hooks_.motor_power) hooks_.motor_power(hooks_.ctx, on);
}

// ---- time -----------------------------------------------------------------------------------
void Firmware::poll(uint32_t now_ms) {
  now_ms_ = now_ms;
  while (since(now_ms, next_tick_ms_) >= 0) {
    timer_tick();
    next_tick_ms_ += kTickMs;
  }
  if (walking_ && since(now_ms, walk_end_ms_) >= 0) stop_walk(kTrialDone);
  write_targets();
}

void Firmware::timer_tick() {
  ++tick_count_;
  if (tick_count_ % telemetry_ticks_ == 0) {
    float pitch = 0.0f, roll = 0.0f, yaw = 0.0f;
    if (hooks_.attitude) hooks_.attitude(hooks_.ctx, &pitch, &roll, &yaw);
    uint8_t frame[26] = {0xFF, 0xFE};
    const float values[6] = {static_cast<float>(tick_count_), pitch, roll, yaw, 0.0f, 0.0f};
    for (int i = 0; i < 6; ++i) write_f32_le(values[i], frame + 2 + 4 * i);
    send(frame, sizeof frame);
  }
  if (tick_count_ % ping_check_ticks_ == 0) {
    if (pings_in_window_ == 0) {
      ++missed_;
      ++stats_.missed_windows;
    } else {
      missed_ = 0;
    }
    pings_in_window_ = 0;
    if (missed_ >= failsafe_windows_ && walking_) {
      ++stats_.failsafe_trips;
      stop_walk(kTrialFailsafe);
    }
  }
  if (health_pending_ && !walking_ && motors_on_) health_check();
}

void Firmware::health_check() {
  health_pending_ = false;
  if (!hooks_.servo_ping) return;
  uint32_t dead = 0;
  for (uint8_t id = kFirstServo; id <= kLastServo; ++id) {
    if (!hooks_.servo_ping(hooks_.ctx, id)) {
      dead |= uint32_t{1} << id;
      const uint8_t frame[4] = {0xFF, 0xFD, kServoPingFailed, id};
      send(frame, 4);
    }
  }
  if (dead == dead_mask_ || !hooks_.servo_write) {
    dead_mask_ = dead;
    return;
  }
  // fold the legs with a dead servo now; a leg whose servos all answer again goes to the
  // gait's first pose
  for (int leg = 0; leg < kLegs; ++leg) {
    const uint32_t servos = uint32_t{7} << (3 * leg + kFirstServo);
    if ((dead_mask_ & servos) && !(dead & servos)) {
      for (int k = 0; k < 3; ++k) pose_[3 * leg + k] = table_.position_rad(0, 3 * leg + k);
    }
  }
  dead_mask_ = dead;
  const float zero[kJoints] = {};
  write(zero);
}

// The fold policy: the live joints of a leg with a dead servo hold the failure pose (a dead
// servo ignores its target anyway). Then the targets go to the servos.
void Firmware::write(const float* velocity) {
  float rate[kJoints];
  for (int j = 0; j < kJoints; ++j) rate[j] = velocity[j];
  for (int leg = 0; leg < kLegs; ++leg) {
    const uint32_t servos = uint32_t{7} << (3 * leg + kFirstServo);
    if (!(dead_mask_ & servos)) continue;
    for (int k = 0; k < 3; ++k) {
      pose_[3 * leg + k] = kFoldPose[k];
      rate[3 * leg + k] = 0.0f;
    }
  }
  hooks_.servo_write(hooks_.ctx, pose_, rate);
}

void Firmware::write_targets() {
  if (!hooks_.servo_write) return;
  if (walking_) {  // the row of the walk's elapsed time, each one once
    const uint32_t elapsed = static_cast<uint32_t>(since(now_ms_, walk_start_ms_));
    const int32_t row = static_cast<int32_t>((uint64_t{elapsed} * kRateHz) / 1000u);
    if (row == last_row_) return;
    last_row_ = row;
    const int r = row % table_.rows;
    float velocity[kJoints];
    for (int j = 0; j < kJoints; ++j) {
      pose_[j] = table_.position_rad(r, j);
      velocity[j] = table_.velocity_rad_s(r, j);
    }
    write(velocity);
    return;
  }
  if (transition_pending_) {  // standing: from where the legs are to the new first pose
    transition_pending_ = false;
    transition_ = true;
    transition_start_ms_ = now_ms_;
    transition_step_ = 0;
    memcpy(transition_from_, pose_, sizeof pose_);
  }
  if (!transition_) return;
  const int32_t steps = static_cast<int32_t>((kPoseTransitionMs * kRateHz) / 1000u);
  const uint32_t elapsed = static_cast<uint32_t>(since(now_ms_, transition_start_ms_));
  int32_t step = static_cast<int32_t>((uint64_t{elapsed} * kRateHz) / 1000u) + 1;
  if (step > steps) step = steps;
  if (step == transition_step_) return;
  transition_step_ = step;
  const float fraction = static_cast<float>(step) / static_cast<float>(steps);
  float zero[kJoints] = {};
  for (int j = 0; j < kJoints; ++j) {
    pose_[j] = transition_from_[j] + fraction * (table_.position_rad(0, j) - transition_from_[j]);
  }
  write(zero);
  if (step == steps) transition_ = false;
}

}  // namespace hexapod_fw
