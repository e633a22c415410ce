#include "io/streamlines/mat_v4.hpp"

#include <fmt/format.h>

#include "intermix/error.hpp"
#include "io/streams/byte_cursor.hpp"
#include "io/streams/header_text.hpp"

namespace imx::detail {
namespace {

constexpr size_t kHeaderBytes = 20;
constexpr int32_t kMaxNameBytes = 4096;
constexpr size_t kMaxMatrices = 65536;

}  // namespace

int mat_v4_value_bytes(int p) {
  static constexpr int kBytes[] = {8, 4, 4, 2, 2, 1};
  return p >= 0 && p <= 5 ? kBytes[p] : 0;
}

std::vector<MatV4Matrix> read_mat_v4(std::string_view bytes, const std::string& what) {
  std::vector<MatV4Matrix> out;
  size_t pos = 0;
  while (pos < bytes.size()) {
    const size_t index = out.size();
    if (index >= kMaxMatrices)
      throw Error(fmt::format("{}: more than {} matrices", what, kMaxMatrices));
    const size_t left = bytes.size() - pos;
    if (left < kHeaderBytes)
      throw Error(fmt::format("{}: the file ends inside the header of matrix {} ({} of {} bytes)",
                              what, index, left, kHeaderBytes));
    // The byte order is the type's M digit (0 little-endian, 1 big-endian): the type field
    // itself is in that order, so whichever reading gives a type of the right M is the one.
    MatV4Matrix m;
    const int32_t little = ByteCursor(bytes.substr(pos, 4), what, false).read<int32_t>("type");
    const int32_t big = ByteCursor(bytes.substr(pos, 4), what, true).read<int32_t>("type");
    int32_t type = little;
    if (little >= 1000 || little < 0) {
      if (big >= 1000 && big < 2000) {
        type = big;
        m.big_endian = true;
      } else if ((little >= 2000 && little < 5000) || (big >= 2000 && big < 5000)) {
        throw Error(
            fmt::format("{}: matrix {} has type {}: VAX and Cray number formats are not read", what,
                        index, little >= 2000 && little < 5000 ? little : big));
      } else {
        throw Error(fmt::format("{}: matrix {} has type field {}, not a MATLAB v4 type (MOPT)",
                                what, index, little));
      }
    }
    ByteCursor header(bytes.substr(pos, kHeaderBytes), what, m.big_endian);
    header.read<int32_t>("type");
    const int32_t rows = header.read<int32_t>("rows");
    const int32_t cols = header.read<int32_t>("columns");
    const int32_t imaginary = header.read<int32_t>("imagf");
    const int32_t name_bytes = header.read<int32_t>("namlen");
    const int o = type / 100 % 10;
    m.precision = type / 10 % 10;
    m.kind = type % 10;
    if (o != 0 || m.precision > 5 || m.kind > 2)
      throw Error(
          fmt::format("{}: matrix {} has type {}, not a MATLAB v4 type (MOPT)", what, index, type));
    if (rows < 0 || cols < 0)
      throw Error(fmt::format("{}: matrix {} claims {} x {} values", what, index, rows, cols));
    if (imaginary != 0 && imaginary != 1)
      throw Error(fmt::format("{}: matrix {} has imagf {}, not 0 or 1", what, index, imaginary));
    if (name_bytes < 1 || name_bytes > kMaxNameBytes ||
        static_cast<size_t>(name_bytes) > left - kHeaderBytes)
      throw Error(
          fmt::format("{}: matrix {} has a name of {} bytes, not 1 to {} within the {} bytes left",
                      what, index, name_bytes, kMaxNameBytes, left - kHeaderBytes));
    const std::string_view raw_name = bytes.substr(pos + kHeaderBytes, name_bytes);
    if (raw_name.back() != '\0')
      throw Error(fmt::format("{}: the name of matrix {} ('{}') does not end in a 0 byte", what,
                              index, shown(raw_name)));
    m.name = std::string(raw_name.substr(0, raw_name.find('\0')));
    m.imaginary = imaginary == 1;
    m.rows = static_cast<uint32_t>(rows);
    m.cols = static_cast<uint32_t>(cols);
    pos += kHeaderBytes + static_cast<size_t>(name_bytes);
    // rows x cols < 2^62 and at most 16 bytes a value: no overflow in 64 bits.
    const uint64_t part = m.count() * static_cast<uint64_t>(mat_v4_value_bytes(m.precision));
    const uint64_t data_bytes = part * (m.imaginary ? 2 : 1);
    if (data_bytes > bytes.size() - pos)
      throw Error(fmt::format(
          "{}: matrix '{}' claims {} x {} values ({} bytes), but only {} bytes are left", what,
          shown(m.name), rows, cols, data_bytes, bytes.size() - pos));
    m.data = bytes.substr(pos, static_cast<size_t>(part));
    pos += static_cast<size_t>(data_bytes);
    if (find_matrix(out, m.name))
      throw Error(fmt::format("{}: matrix '{}' appears twice", what, shown(m.name)));
    out.push_back(std::move(m));
  }
  return out;
}

const MatV4Matrix* find_matrix(const std::vector<MatV4Matrix>& matrices, std::string_view name) {
  for (const MatV4Matrix& m : matrices)
    if (m.name == name) return &m;
  return nullptr;
}

std::vector<double> mat_v4_numbers(const MatV4Matrix& m, std::optional<uint64_t> expected,
                                   const std::string& what) {
  if (m.kind != 0 || m.imaginary)
    throw Error(fmt::format("{}: matrix '{}' is {}, not a real numeric matrix", what, shown(m.name),
                            m.kind == 1   ? "text"
                            : m.kind == 2 ? "a sparse matrix"
                                          : "complex"));
  if (expected && m.count() != *expected)
    throw Error(fmt::format("{}: matrix '{}' holds {} x {} values, not {}", what, shown(m.name),
                            m.rows, m.cols, *expected));
  std::vector<double> out;
  out.reserve(static_cast<size_t>(m.count()));
  ByteCursor in(m.data, what, m.big_endian);
  for (uint64_t i = 0; i < m.count(); ++i) {
    switch (m.precision) {
      case 0:
        out.push_back(in.read<double>("a value"));
        break;
      case 1:
        out.push_back(in.read<float>("a value"));
        break;
      case 2:
        out.push_back(in.read<int32_t>("a value"));
        break;
      case 3:
        out.push_back(in.read<int16_t>("a value"));
        break;
      case 4:
        out.push_back(in.read<uint16_t>("a value"));
        break;
      default:
        out.push_back(in.read<uint8_t>("a value"));
        break;
    }
  }
  return out;
}

}  // namespace imx::detail
