// The files this process has opened as inputs, by identity (device and inode), so that an output
// that names one of them (directly, through a symbolic link or a hard link) is refused before it
// replaces the input (issue 48, "outputs never replace inputs").
#pragma once
#include <filesystem>
#include <optional>
#include <string>

#include <sys/stat.h>

namespace imx {

// Records the file `st` describes (from fstat on an opened input) as an input, named `file`.
void note_input(const struct stat& st, const std::filesystem::path& file);

// The name an input was opened by when `output` exists and is that same file once links are
// resolved (same device, inode and modification time); nullopt otherwise.
std::optional<std::filesystem::path> input_named_by(const std::filesystem::path& output);

// Throws imx::FileError "OUT: is an input of this command (IN); choose another output" when
// `output` names an input; nothing is written.
void refuse_output_over_input(const std::filesystem::path& output);

}  // namespace imx
