// Input and output paths must be regular files: a FIFO blocks its reader forever, and a device
// named as output would be replaced by a file (issue 17's "non-regular files" class).
#pragma once
#include <filesystem>
#include <string>

namespace imx {

// Throws imx::Error naming `file` unless it exists and is a regular file once symbolic links are
// followed: "no such file", "is a directory", "is a FIFO (named pipe)", a device or socket, or a
// symbolic link loop, each said as such. It is open_input (input_file.hpp) and a close: the
// check is on an open descriptor, never blocks, and records the file as an input.
// `what` names the file in the message when given (e.g. "x.raw (data file of x.nhdr)").
void require_regular_file(const std::filesystem::path& file, const std::string& what = {});

// The data file that `reference` in a header names (e.g. "field 'data file'"): relative names
// resolve against the header's folder.
// Unless InputLimits::allow_external_data, it must lie inside that folder once links are
// resolved, so that a header cannot read any file on the machine; a name that cannot be
// resolved (a symbolic link loop) is an imx::FileError saying so. Must be a regular file.
std::filesystem::path resolve_data_file(const std::filesystem::path& header,
                                        const std::string& name, const std::string& reference);

// Throws imx::Error naming `file` when it exists and is not a regular file (an output may be new).
void require_regular_or_new_file(const std::filesystem::path& file);

}  // namespace imx
