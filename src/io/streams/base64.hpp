// Base64 (RFC 4648) as XML formats store binary arrays in text: GIfTI and VTK's .vtp.
#pragma once

namespace imx::detail {

// The 6-bit value of one base64 character, -1 for any other (padding '=' and white space
// included: the callers decide what those mean).
constexpr int base64_value(unsigned char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

}  // namespace imx::detail
