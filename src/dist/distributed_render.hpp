// Distributed rendering over MPI (sort-last, deep): every rank loads and renders its part of
// the scene into per-sample slab arrays (the zSlab pipeline before its final composite), the
// arrays are composited by binary swap with the intermix kernel, and rank 0 writes the image.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "dist/partition.hpp"

namespace imx {

struct DistributedRequest {
  std::filesystem::path scene;
  std::vector<std::string> overrides;  // --set, --width, --height
  std::string method;                  // empty, zslab or zslab-hybrid (both run as zslab)
  int spp = 0;                         // 0: the scene's, else 1
  int threads = 0;                     // per rank; 0: the node's cores shared by its ranks
  PartitionMode partition = PartitionMode::automatic;
  std::filesystem::path output;  // PNG, written by rank 0
  bool linear = false;
  std::filesystem::path report;  // JSON timings, bytes and memory per rank (optional)
  bool progress = false;         // rank 0 draws a progress bar
};

// False when intermix was built without MPI; `why` then says so.
bool distributed_available(std::string* why = nullptr);

// Runs one distributed frame as one rank of the MPI job this process belongs to (a single
// process without mpirun is a job of one), initializing and finalizing MPI; returns the exit
// status. When any rank fails before compositing (a missing file, a bad header, out of memory)
// every rank passes the same message, "rank K of R: ...", to `print_error` before any exits,
// and returns 1. A failure during compositing ends the job (MPI_Abort), so no rank waits for
// ever. Built without MPI, throws imx::Error saying so.
int render_distributed(const DistributedRequest& request,
                       const std::function<void(const std::string&)>& print_error);

}  // namespace imx
