// Compiled for AVX2 and FMA outside any run-time dispatch (tests/CMakeLists.txt): the function
// scripts/check-baseline-isa must name, so that its pass on the programs means something.
float wide_outside_dispatch(const float* a, const float* b, int n) {
  float sum = 0.0f;
  for (int i = 0; i < n; ++i) sum += a[i] * b[i];
  return sum;
}
