// What Zarr v2's .zarray and v3's zarr.json parsers share: refusals naming the field, sizes,
// fill values and the chunk budget.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "intermix/error.hpp"
#include "io/zarr/zarr_array.hpp"

namespace imx::detail {

// Metadata files are small documents; more is not metadata.
inline constexpr uintmax_t kMaxZarrMetadataBytes = 1 << 20;
inline constexpr int kMaxZarrJsonDepth = 32;

// "`what`: field 'F' VALUE WHY", the value shortened.
Error zarr_bad_field(const std::string& what, std::string_view field, const nlohmann::json& value,
                     std::string_view why);

// `value` (a list of 1 to 32 integers >= `smallest`, each below 2^31), else refused by field.
std::vector<int64_t> zarr_sizes(const nlohmann::json& value, std::string_view field,
                                const std::string& what, int64_t smallest);

// The JSON text of a metadata file as an object, refused naming `what` when it is not one.
nlohmann::json parse_zarr_json(std::string_view text, const std::string& what);

// Sets a.fill from a fill value (null, a number, a boolean; for floats also "NaN", "Infinity",
// "-Infinity" and, when `hex_floats`, v3's "0x..." bit patterns), in a's byte order.
void set_zarr_fill(const nlohmann::json& value, ZarrArray& a, bool hex_floats);

// a.chunk_bytes from a.chunks, refused (naming `field`) past the voxel limit or memory budget.
void set_zarr_chunk_bytes(ZarrArray& a, std::string_view field, const nlohmann::json& value);

}  // namespace imx::detail
