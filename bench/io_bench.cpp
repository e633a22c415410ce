// Micro-benchmarks of reading clinical data in-process (no program start-up, no output file):
// the Philips DICOM series of ../shared/data, and dcm2niix's NIfTI of it for scale.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "intermix/dicom.hpp"
#include "intermix/io.hpp"

namespace imx {
namespace {

const std::filesystem::path kData = IMX_SHARED_DATA;

void BM_ReadDicomPhilips(benchmark::State& state) {
  const std::filesystem::path folder = kData / "dicom/ct-philips";
  if (!std::filesystem::exists(folder)) return state.SkipWithError("no ../shared/data");
  for (auto _ : state) benchmark::DoNotOptimize(read_dicom(folder).volume.voxel_count());
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * 512 * 512 * 28 * 2);
}
BENCHMARK(BM_ReadDicomPhilips)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ListDicomPhilips(benchmark::State& state) {
  const std::filesystem::path folder = kData / "dicom/ct-philips";
  if (!std::filesystem::exists(folder)) return state.SkipWithError("no ../shared/data");
  for (auto _ : state) benchmark::DoNotOptimize(list_dicom_series(folder).size());
}
BENCHMARK(BM_ListDicomPhilips)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ReadNiftiPhilips(benchmark::State& state) {
  const std::filesystem::path file = kData / "dicom/ref/ct-philips.nii.gz";
  if (!std::filesystem::exists(file)) return state.SkipWithError("no ../shared/data");
  for (auto _ : state) benchmark::DoNotOptimize(read_volume(file).voxel_count());
}
BENCHMARK(BM_ReadNiftiPhilips)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace imx
