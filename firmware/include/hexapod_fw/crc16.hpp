// CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection, no final xor): the check of the
// extension frames (docs/radio-protocol.md). crc16("123456789") == 0x29B1.
#pragma once
#include <stddef.h>
#include <stdint.h>

namespace hexapod_fw {

uint16_t crc16(const uint8_t* data, size_t n, uint16_t crc = 0xFFFF);

}  // namespace hexapod_fw
