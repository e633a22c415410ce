// The project's shared data (../shared/data beside the checkout, IMX_SHARED_DATA): real and
// third-party files that some checkouts lack, so that the tests reading them skip there.
#pragma once
#include <filesystem>
#include <initializer_list>

#include <gtest/gtest.h>

namespace imx::test {

// `name` in the shared data folder (an absolute `name` stays as it is); the folder without one.
inline std::filesystem::path shared_data(const std::filesystem::path& name = {}) {
  return std::filesystem::path(IMX_SHARED_DATA) / name;
}

// The first of `names` (as shared_data takes them) that is absent, or an empty path.
inline std::filesystem::path missing_shared_data(
    std::initializer_list<std::filesystem::path> names) {
  for (const std::filesystem::path& name : names)
    if (!std::filesystem::exists(shared_data(name))) return shared_data(name);
  return {};
}

}  // namespace imx::test

// Skips the running test unless every one of the named files or folders of the shared data is
// there: SKIP_WITHOUT_SHARED_DATA("FLAIR.nrrd", "FLAIR.nii.gz").
#define SKIP_WITHOUT_SHARED_DATA(...)                                                             \
  if (const std::filesystem::path imx_missing_ = ::imx::test::missing_shared_data({__VA_ARGS__}); \
      !imx_missing_.empty())                                                                      \
  GTEST_SKIP() << "no " << imx_missing_.string() << " (the shared data is absent)"
