// CRC-32C (Castagnoli), the checksum of Zarr v3's crc32c codec (RFC 3720's polynomial).
#pragma once
#include <cstdint>
#include <span>

namespace imx::detail {

// The CRC-32C of `bytes` (reflected, initial and final xor 0xFFFFFFFF: crc32c("123456789") is
// 0xE3069283).
uint32_t crc32c(std::span<const uint8_t> bytes);

}  // namespace imx::detail
