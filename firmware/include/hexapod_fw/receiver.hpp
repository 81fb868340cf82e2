// Receive path v2 (docs/radio-protocol.md): 10-byte frames, each window validated; while a window
// is invalid the receiver slides by one byte. Fed one byte at a time, from the radio UART's
// receive interrupt or a DMA ring drained in the main loop.
#pragma once
#include <stdint.h>

namespace hexapod_fw {

constexpr int kFrameLen = 10;

enum class FrameKind : uint8_t { kNone, kPing, kMovement, kLegacyCommand, kExtension };

struct ReceiverStats {
  uint32_t frames_ok;
  uint32_t checksum_errors;  // CRC or 8-bit sum did not match
  uint32_t implausible;      // a movement frame with impossible fields
  uint32_t resyncs;          // runs of skipped bytes
  uint32_t bytes_dropped;
};

class Receiver {
 public:
  // Take one byte; returns the kind of frame it completes (kNone if none). The frame's bytes
  // are then in frame() until the next call.
  FrameKind push(uint8_t byte);
  const uint8_t* frame() const { return frame_; }
  const ReceiverStats& stats() const { return stats_; }

 private:
  FrameKind classify();  // the window in buf_ (kFrameLen bytes)
  void drop_one();

  uint8_t buf_[kFrameLen] = {};
  uint8_t frame_[kFrameLen] = {};
  uint8_t len_ = 0;
  bool skipping_ = false;
  ReceiverStats stats_ = {};
};

}  // namespace hexapod_fw
