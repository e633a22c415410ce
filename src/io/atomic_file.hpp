// Atomic file writing: output goes to a temporary file beside the target, then a rename.
#pragma once
#include <filesystem>
#include <functional>
#include <ostream>

namespace imx {

// Calls `write` with a binary stream on a new temporary file in `file`'s folder, then renames
// it over `file`, so readers never see a half-written file. When `write` throws or any I/O
// step fails, the temporary file is removed and the error (an imx::Error naming `file`)
// propagates; an existing `file` is then left untouched.
void write_file_atomically(const std::filesystem::path& file,
                           const std::function<void(std::ostream&)>& write);

}  // namespace imx
