// MATLAB version 4 MAT files (DSI Studio's .tt, .fib and .src): a run of matrices, each a
// 20-byte header (type, rows, columns, imaginary flag, name length), its name and its values.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace imx::detail {

struct MatV4Matrix {
  std::string name;
  int precision = 0;  // P of the type MOPT: 0 double, 1 single, 2 int32, 3 int16, 4 uint16, 5 uint8
  int kind = 0;       // T: 0 numeric, 1 text, 2 sparse
  bool big_endian = false;
  bool imaginary = false;
  uint32_t rows = 0, cols = 0;
  std::string_view data;  // the real part's bytes, column by column

  uint64_t count() const { return uint64_t{rows} * cols; }
};

// Bytes of one value of precision `p` (0 to 5).
int mat_v4_value_bytes(int p);

// The matrices of `bytes`, whose data views point into it. Every header is checked: a type that
// is no MATLAB v4 type (or a VAX or Cray number format), a name that is not terminated, and a
// size larger than the bytes left are imx::Errors naming `what` and the matrix.
std::vector<MatV4Matrix> read_mat_v4(std::string_view bytes, const std::string& what);

// The matrix named `name`, if any (the first: a later one of the same name is an error that
// read_mat_v4 reports).
const MatV4Matrix* find_matrix(const std::vector<MatV4Matrix>& matrices, std::string_view name);

// A real numeric matrix's values as doubles, in the file's order; imx::Error naming `what` and
// the matrix unless it is numeric, real and holds exactly `expected` values (any count when
// nullopt).
std::vector<double> mat_v4_numbers(const MatV4Matrix& m, std::optional<uint64_t> expected,
                                   const std::string& what);

}  // namespace imx::detail
