// The templates of format_registry.hpp.
#pragma once
#include <utility>

#include "intermix/error.hpp"

namespace imx::detail {

template <class Row>
const Row* find_format(std::span<const Row> rows, const FileProbe& probe, bool* wrapped) {
  if (wrapped) *wrapped = false;
  for (const Row& row : rows)
    if (row.info.sniff && row.info.sniff(probe)) return &row;
  const Row* best = nullptr;
  size_t best_length = 0;
  for (const Row& row : rows) {
    const size_t length = matched_extension(row.info, probe.name).size();
    if (length > best_length) best = &row, best_length = length;
  }
  if (best || !probe.name.ends_with(".gz")) return best;
  // x.obj.gz: the row of x.obj, read through an inflated copy when the row allows it.
  const std::string_view inner = std::string_view(probe.name).substr(0, probe.name.size() - 3);
  for (const Row& row : rows)
    for (std::string_view ext : row.info.gz_wrapped)
      if (ext.size() > best_length && inner.size() > ext.size() && inner.ends_with(ext))
        best = &row, best_length = ext.size();
  if (best && wrapped) *wrapped = true;
  return best;
}

}  // namespace imx::detail
