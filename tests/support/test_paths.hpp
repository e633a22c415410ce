// Where the tests find their files and programs. Every test compile includes this header
// (-include, tests/CMakeLists.txt); the paths themselves are defined once per test program in a
// file the build generates (<build>/tests/test_<module>_paths.cpp). No test compile then names
// the folder of its checkout, so ccache serves them to a clone in another folder (docs/ci.md).
// Each macro is a const char*: pass it to std::filesystem::path or std::string.
#pragma once

namespace imx::test_paths {
extern const char* const shared_data;    // ../shared/data beside the checkout
extern const char* const examples_dir;   // examples/
extern const char* const golden_dir;     // tests/golden/
extern const char* const bench_scenes;   // bench/scenes/
extern const char* const web_dir;        // web/ (the viewer's page)
extern const char* const cli_path;       // the intermix program of this build
extern const char* const lab_path;       // the intermix-lab program of this build
}  // namespace imx::test_paths

#define IMX_SHARED_DATA (::imx::test_paths::shared_data)
#define IMX_EXAMPLES_DIR (::imx::test_paths::examples_dir)
#define IMX_GOLDEN_DIR (::imx::test_paths::golden_dir)
#define IMX_BENCH_SCENES_DIR (::imx::test_paths::bench_scenes)
#define IMX_CLI_PATH (::imx::test_paths::cli_path)
#define IMX_LAB_PATH (::imx::test_paths::lab_path)
// imx_server gives its users IMX_WEB_DIR on the command line; the tests take the same folder
// from here instead.
#undef IMX_WEB_DIR
#define IMX_WEB_DIR (::imx::test_paths::web_dir)
