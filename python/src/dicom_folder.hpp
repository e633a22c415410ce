// DICOM folders as read_volume(folder) reads them: the folder's own files only, unless the caller
// asks for its subfolders too (the engine's reader scans a folder recursively).
#pragma once
#include <filesystem>
#include <functional>

namespace imx::python {

// Runs `read` on the DICOM source to read. For a folder with subfolders read without
// `recursive`, that is a temporary folder of links to the folder's own files, and errors name
// the folder instead of it; a folder whose files all lie in subfolders is refused at once,
// naming them and `recursive=True`. Any other source is read as it is.
void read_dicom_source(const std::filesystem::path& source, bool recursive, const char* function,
                       const std::function<void(const std::filesystem::path&)>& read);

}  // namespace imx::python
