// Input and output paths must be regular files: a FIFO blocks its reader forever, and a device
// named as output would be replaced by a file (issue 17's "non-regular files" class).
#pragma once
#include <filesystem>
#include <string>

namespace imx {

// Throws imx::Error naming `file` unless it exists and is a regular file once symbolic links are
// followed: "no such file", "is a directory", "is a FIFO (named pipe)", a device or socket, or a
// symbolic link loop, each said as such.
// `what` names the file in the message when given (e.g. "x.raw (data file of x.nhdr)").
void require_regular_file(const std::filesystem::path& file, const std::string& what = {});

// Throws imx::Error naming `file` when it exists and is not a regular file (an output may be new).
void require_regular_or_new_file(const std::filesystem::path& file);

}  // namespace imx
