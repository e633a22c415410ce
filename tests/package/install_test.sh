#!/usr/bin/env bash
# The C++ package from outside: installs the build into a fresh prefix, then
#   1. checks what was installed (headers, static libraries, CMake package, .pc file, program),
#   2. compiles every public header alone against the installed include folder only, and checks
#      that it includes nothing but the standard library, glm and other public headers,
#   3. configures and builds examples/cpp as a project of its own (find_package(intermix)),
#      runs it on examples/fusion.json at 64x64 and checks the PNG and that the second frame
#      re-ran fewer stages than the first,
#   4. builds and runs a one-file program with the flags of pkg-config --cflags --libs intermix,
#   5. runs the installed program.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR WORK_DIR CXX [EXTRA_FLAGS]
#   WORK_DIR is emptied first and kept afterwards (the logs are there); EXTRA_FLAGS go to every
#   compile and link (the sanitizer build's -fsanitize=..., whose libraries need its runtime).
# Exit 77 (skipped) when cmake or ninja is missing.
set -uo pipefail
if [ $# -lt 4 ]; then
  sed -n '2,14p' "$0" >&2
  exit 2
fi
build=$(realpath "$1") source=$(realpath "$2") work=$(realpath -m "$3") cxx=$4 flags=${5:-}
for tool in cmake ninja; do
  if ! command -v "$tool" >/dev/null; then
    echo "SKIP: $tool not found"
    exit 77
  fi
done

fail() {
  echo "FAIL: $*" >&2
  exit 1
}
t0=$(date +%s%N)
step() {
  local ms=$((($(date +%s%N) - t0) / 1000000))
  printf '[%3d.%d s] %s\n' $((ms / 1000)) $((ms % 1000 / 100)) "$*"
}
# Runs a command with its output in $work/LOG; on failure prints the log's end.
logged() {
  local log=$work/$1
  shift
  if ! "$@" >"$log" 2>&1; then
    tail -n 40 "$log" >&2
    fail "$* (log: $log)"
  fi
}

rm -rf "$work"
mkdir -p "$work"
prefix=$work/prefix
read -r -a extra <<<"$flags"

step "install into $prefix"
logged install.log cmake --install "$build" --prefix "$prefix"
for f in include/intermix/renderer.hpp include/intermix/io.hpp \
         lib/cmake/intermix/intermixConfig.cmake lib/cmake/intermix/intermixConfigVersion.cmake \
         lib/cmake/intermix/intermixTargets.cmake lib/pkgconfig/intermix.pc \
         bin/intermix share/intermix/web/index.html share/intermix/web/js/main.js \
         lib/intermix/libimx_dicom_codec.so lib/intermix/libimx_mesh_assimp.so \
         lib/intermix/libimx_minc_hdf5.so; do
  [ -f "$prefix/$f" ] || fail "not installed: $f"
done
for m in methods frame csg scene presets phantoms io_mesh io_volume io_dicom io_image io_voxels \
         io_registry io_streams metrics raster volume core; do
  [ -f "$prefix/lib/libimx_$m.a" ] || fail "not installed: lib/libimx_$m.a"
done
# The MPI plugin, when the build has one (Open MPI found): opened by render --distributed.
if [ -f "$build/libimx_mpi.so" ]; then
  [ -f "$prefix/lib/intermix/libimx_mpi.so" ] || fail "not installed: lib/intermix/libimx_mpi.so"
fi
[ ! -e "$prefix/lib/libimx_server.a" ] || fail "imx_server is installed but is no public API"
[ ! -e "$prefix/lib/libimx_probes.a" ] || fail "imx_probes is installed but is no public API"
[ -z "$(find "$prefix/include" -type f ! -path "$prefix/include/intermix/*.hpp")" ] ||
  fail "files besides include/intermix/*.hpp in the include folder"
if grep -qF -e "$source/" -e "$build/" "$prefix"/lib/cmake/intermix/*.cmake "$prefix/lib/pkgconfig/intermix.pc"; then
  fail "the installed package names the source or build tree"
fi

step "public headers: includes, and each compiles alone"
headers=("$prefix"/include/intermix/*.hpp)
[ ${#headers[@]} -ge 10 ] || fail "only ${#headers[@]} public headers installed"
# Allowed: <standard> (no folder, no .h), <glm/...>, and intermix/ headers.
bad=$(grep -Hn '^[[:space:]]*#[[:space:]]*include' "${headers[@]}" |
  grep -Ev '#[[:space:]]*include[[:space:]]*(<[a-z_]+>|<glm/[^>]+>|"intermix/[a-z_]+\.hpp"|<intermix/[a-z_]+\.hpp>)')
[ -z "$bad" ] || fail "public headers include internal or third-party headers:
$bad"
mkdir -p "$work/headers"
pids=()
for h in "${headers[@]}"; do
  name=$(basename "$h" .hpp)
  printf '#include <intermix/%s.hpp>\n#include <intermix/%s.hpp>\n' "$name" "$name" >"$work/headers/$name.cpp"
  "$cxx" -std=c++20 "${extra[@]}" -Wall -Wextra -Werror -fsyntax-only -I"$prefix/include" \
    "$work/headers/$name.cpp" >"$work/headers/$name.log" 2>&1 &
  pids+=("$!:$name")
done
for p in "${pids[@]}"; do
  if ! wait "${p%%:*}"; then
    cat "$work/headers/${p#*:}.log" >&2
    fail "intermix/${p#*:}.hpp does not compile alone against the installed headers"
  fi
done

step "examples/cpp against the installed package (find_package)"
logged configure.log cmake -S "$source/examples/cpp" -B "$work/example" -G Ninja \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags"
logged build.log cmake --build "$work/example"
step "render_twice on fusion.json at 64x64"
png=$work/fusion.png
logged render_twice.log "$work/example/render_twice" "$source/examples/fusion.json" "$png" \
  image.width=64 image.height=64 objects.ct.source.size=64 objects.pet.source.size=64
cat "$work/render_twice.log"
[ -s "$png" ] || fail "render_twice wrote no $png"
[ "$(head -c 8 "$png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "$png is no PNG"
[ "$(od -An -tu1 -j16 -N8 "$png" | tr -s ' ' | sed 's/^ //')" = "0 0 0 64 0 0 0 64" ] ||
  fail "$png is not 64x64"
stats() { sed -n "s/^$1: .*, stages \([0-9]*\), stages_run \([0-9]*\)\$/\1 \2/p" "$work/render_twice.log"; }
read -r stages1 run1 <<<"$(stats first)"
read -r stages2 run2 <<<"$(stats second)"
[ -n "${run1:-}" ] && [ -n "${run2:-}" ] || fail "no stage counts in render_twice's output"
[ "$stages1" -gt 1 ] && [ "$stages2" -eq "$stages1" ] || fail "stages: $stages1, then $stages2"
[ "$run2" -lt "$run1" ] || fail "the second frame re-ran $run2 stages, the first $run1"

step "pkg-config --cflags --libs intermix, and a one-file program built with them"
export PKG_CONFIG_PATH=$prefix/lib/pkgconfig
pc=$(pkg-config --cflags --libs intermix) || fail "pkg-config --cflags --libs intermix"
echo "pkg-config: $pc"
[ "$(pkg-config --modversion intermix)" = "$(sed -n 's/^set(PACKAGE_VERSION "\(.*\)")$/\1/p' "$prefix/lib/cmake/intermix/intermixConfigVersion.cmake")" ] ||
  fail "the .pc file's version is not the CMake package's"
mkdir -p "$work/pkgconfig"
cat >"$work/pkgconfig/app.cpp" <<'CPP'
#include <cstdio>

#include <intermix/io.hpp>
#include <intermix/render.hpp>
#include <intermix/scene.hpp>

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const imx::Scene scene = imx::parse_scene(
      R"({"image": {"width": 24, "height": 16},
          "objects": [{"name": "ct", "type": "volume", "source": {"phantom": "ct-head", "size": 32},
                       "transfer_function": {"preset": "ct-bone"}}]})",
      ".", "app");
  imx::RenderOptions options;
  options.method = "mdvr";
  imx::write_png(imx::render(scene, options), argv[1]);
  const imx::Image back = imx::read_png(argv[1]);
  std::printf("%dx%d\n", back.width(), back.height());
  return back.width() == 24 && back.height() == 16 ? 0 : 1;
}
CPP
read -r -a pc_flags <<<"$pc"
logged pkgconfig.log "$cxx" -std=c++20 "${extra[@]}" "$work/pkgconfig/app.cpp" "${pc_flags[@]}" \
  -o "$work/pkgconfig/app"
logged pkgconfig-run.log "$work/pkgconfig/app" "$work/pkgconfig/app.png"

step "the installed program"
logged cli.log "$prefix/bin/intermix" info --phantom ct-head --size 16
# A compressed DICOM file (JPEG lossless) is decoded by the installed codec plugin, found beside
# the installed program (LD_DEBUG=files: the dynamic loader names what it maps).
jpeg=$source/../shared/data/dicom/ts/5.dcm
if [ -f "$jpeg" ]; then
  step "the installed program decodes $jpeg with the installed codec plugin"
  LD_DEBUG=files logged codec.log "$prefix/bin/intermix" -q convert "$jpeg" -o "$work/ts5.nii"
  grep -qF "file=$prefix/lib/intermix/libimx_dicom_codec.so [0];  generating link map" \
    "$work/codec.log" || fail "the installed program did not load $prefix/lib/intermix/libimx_dicom_codec.so (log: $work/codec.log)"
fi
# An OBJ mesh is read by the installed mesh plugin (assimp), found the same way.
step "the installed program reads an OBJ mesh with the installed mesh plugin"
printf 'v 0 0 0\nv 10 0 0\nv 10 10 0\nv 0 10 0\nf 1 2 3 4\n' >"$work/square.obj"
LD_DEBUG=files logged mesh.log "$prefix/bin/intermix" info "$work/square.obj"
grep -qF "file=$prefix/lib/intermix/libimx_mesh_assimp.so [0];  generating link map" \
  "$work/mesh.log" || fail "the installed program did not load $prefix/lib/intermix/libimx_mesh_assimp.so (log: $work/mesh.log)"
grep -qE '^triangles +2$' "$work/mesh.log" || fail "the installed program read no 2 triangles from square.obj (log: $work/mesh.log)"
step "PASS"
