#include "hexapod_fw/crc16.hpp"

namespace hexapod_fw {

namespace {
// The table is built at compile time into flash (512 B), so no start-up work and no RAM.
struct Table {
  uint16_t v[256];
  constexpr Table() : v() {
    for (int byte = 0; byte < 256; ++byte) {
      uint16_t crc = static_cast<uint16_t>(byte << 8);
      for (int bit = 0; bit < 8; ++bit) {
        crc = (crc & 0x8000) ? static_cast<uint16_t>((crc << 1) ^ 0x1021)
                             : static_cast<uint16_t>(crc << 1);
      }
      v[byte] = crc;
    }
  }
};
constexpr Table kTable;
}  // namespace

uint16_t crc16(const uint8_t* data, size_t n, uint16_t crc) {
  for (size_t i = 0; i < n; ++i) {
    crc = static_cast<uint16_t>((crc << 8) ^ kTable.v[((crc >> 8) ^ data[i]) & 0xFF]);
  }
  return crc;
}

}  // namespace hexapod_fw
