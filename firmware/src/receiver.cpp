#include "hexapod_fw/receiver.hpp"

#include "hexapod_fw/crc16.hpp"
#include "hexapod_fw/generated.hpp"

namespace hexapod_fw {

namespace {
// Legacy FF commands, and where each one's zero padding starts.
int ff_padding(uint8_t code) {
  switch (code) {
    case 0xFA: return 3;  // motor power
    case 0xFB: return 4;  // levelling PID on/off
    case 0xDE: return 8;  // PID gain
    case 0xDD: return 6;  // telemetry period
    case 0xF8: return 4;  // charging base
    default: return -1;
  }
}

bool zero_from(const uint8_t* b, int first) {
  for (int i = first; i < kFrameLen; ++i) {
    if (b[i] != 0) return false;
  }
  return true;
}
}  // namespace

FrameKind Receiver::push(uint8_t byte) {
  // Every window a byte completes is judged at once; an invalid one costs one byte, so at most
  // kFrameLen - 1 windows are judged per byte (the buffer never holds more than 10 bytes).
  buf_[len_++] = byte;
  while (len_ == kFrameLen) {
    FrameKind kind = classify();
    if (kind == FrameKind::kNone) {
      drop_one();
      continue;
    }
    for (int i = 0; i < kFrameLen; ++i) frame_[i] = buf_[i];
    len_ = 0;
    skipping_ = false;
    ++stats_.frames_ok;
    return kind;
  }
  return FrameKind::kNone;
}

void Receiver::drop_one() {
  if (!skipping_) {
    ++stats_.resyncs;
    skipping_ = true;
  }
  ++stats_.bytes_dropped;
  for (int i = 1; i < kFrameLen; ++i) buf_[i - 1] = buf_[i];
  len_ = kFrameLen - 1;
}

FrameKind Receiver::classify() {
  const uint8_t* b = buf_;
  if (b[0] == kMarker) {
    uint16_t crc = static_cast<uint16_t>((b[8] << 8) | b[9]);
    if (crc16(b, 8) == crc) return FrameKind::kExtension;
    ++stats_.checksum_errors;
    return FrameKind::kNone;
  }
  if (b[0] == 0x01) {
    unsigned sum = 0;
    for (int i = 0; i < 9; ++i) sum += b[i];
    if ((sum & 0xFF) != b[9]) {
      ++stats_.checksum_errors;
      return FrameKind::kNone;
    }
    // markers 02/03/04, a known direction, a height of 50..240 mm (280 * b6 / 100)
    unsigned height = 280u * b[6];
    if (b[3] != 0x02 || b[5] != 0x03 || b[7] != 0x04 || b[1] > 8 || height < 5000 ||
        height > 24000) {
      ++stats_.implausible;
      return FrameKind::kNone;
    }
    return FrameKind::kMovement;
  }
  // No checksum: aligned, taken as today's firmware takes them; while resynchronising only in
  // the exact form the bridge sends (zero padding), so garbage cannot pass for them.
  if (b[0] == kPingByte) {
    return (!skipping_ || zero_from(b, 1)) ? FrameKind::kPing : FrameKind::kNone;
  }
  if (b[0] == 0xFF) {
    int pad = ff_padding(b[1]);
    if (pad < 0) return FrameKind::kNone;
    if (skipping_ && !zero_from(b, pad)) return FrameKind::kNone;
    return FrameKind::kLegacyCommand;
  }
  return FrameKind::kNone;
}

}  // namespace hexapod_fw
