#include "io/registry/tiff_sniff.hpp"

#include "io/streams/header_text.hpp"

namespace imx::detail {

bool is_tiff_head(std::string_view head) {
  using namespace std::string_view_literals;
  if (head.size() < 8) return false;
  const std::string_view magic = head.substr(0, 4);
  const bool tiff =
      magic == "II*\0"sv || magic == "MM\0*"sv || magic == "II+\0"sv || magic == "MM\0+"sv;
  return tiff && !(head.size() >= 132 && head.substr(128, 4) == "DICM");
}

bool has_tiff_extension(const std::filesystem::path& path) {
  const std::string ext = lower(path.extension().string());
  return ext == ".tif" || ext == ".tiff";
}

bool is_tiff_folder(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return false;
  std::filesystem::directory_iterator it(dir, ec), end;
  if (ec) return false;
  bool any = false;
  for (; it != end; it.increment(ec)) {
    if (ec) return false;
    const std::string name = it->path().filename().string();
    if (name.empty() || name[0] == '.' || !it->is_regular_file(ec)) continue;
    if (!has_tiff_extension(it->path())) return false;
    any = true;
  }
  return any;
}

}  // namespace imx::detail
