// The MPI plugin: the calls of mpi_plugin_abi.h on Open MPI's C API, for
// intermix render --distributed (src/dist/distributed_render.cpp opens it when a distributed
// frame starts). Every call is on MPI_COMM_WORLD from the main thread.
#include "dist_mpi/mpi_plugin_abi.h"

#include <mpi.h>

namespace {

MPI_Datatype mpi_type(int32_t type) {
  switch (type) {
    case IMX_MPI_CHAR:
      return MPI_CHAR;
    case IMX_MPI_INT:
      return MPI_INT;
    case IMX_MPI_UINT64:
      return MPI_UINT64_T;
    case IMX_MPI_FLOAT:
      return MPI_FLOAT;
    case IMX_MPI_DOUBLE:
      return MPI_DOUBLE;
    default:
      return MPI_BYTE;
  }
}

void init(int32_t* rank, int32_t* size, int32_t* node_ranks, int32_t* owner) {
  int ready = 0;
  MPI_Initialized(&ready);
  *owner = 0;
  if (!ready) {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    *owner = 1;
  }
  int r = 0, s = 1, n = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  MPI_Comm_size(MPI_COMM_WORLD, &s);
  MPI_Comm node;  // the ranks sharing this machine, which share its cores
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, r, MPI_INFO_NULL, &node);
  MPI_Comm_size(node, &n);
  MPI_Comm_free(&node);
  *rank = r;
  *size = s;
  *node_ranks = n;
}

void finalize() {
  MPI_Finalize();
}

void barrier() {
  MPI_Barrier(MPI_COMM_WORLD);
}

void abort_job(int32_t code) {
  MPI_Abort(MPI_COMM_WORLD, code);
}

void allreduce_min_int(const int32_t* in, int32_t* out) {
  MPI_Allreduce(in, out, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
}

void bcast(void* data, int32_t count, int32_t type, int32_t root) {
  MPI_Bcast(data, count, mpi_type(type), root, MPI_COMM_WORLD);
}

void send(const void* data, int32_t count, int32_t type, int32_t to, int32_t tag) {
  MPI_Send(data, count, mpi_type(type), to, tag, MPI_COMM_WORLD);
}

void recv(void* data, int32_t count, int32_t type, int32_t from, int32_t tag) {
  MPI_Recv(data, count, mpi_type(type), from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
}

void sendrecv(const void* out, int32_t out_count, void* in, int32_t in_count, int32_t type,
              int32_t partner, int32_t tag) {
  MPI_Sendrecv(out, out_count, mpi_type(type), partner, tag, in, in_count, mpi_type(type), partner,
               tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
}

void gather(const void* mine, int32_t count, void* all, int32_t type, int32_t root) {
  MPI_Gather(mine, count, mpi_type(type), all, count, mpi_type(type), root, MPI_COMM_WORLD);
}

void gatherv(const void* mine, int32_t count, void* all, const int32_t* counts,
             const int32_t* displs, int32_t type, int32_t root) {
  MPI_Gatherv(mine, count, mpi_type(type), all, counts, displs, mpi_type(type), root,
              MPI_COMM_WORLD);
}

constexpr imx_mpi_calls kCalls{&init,   &finalize, &barrier, &abort_job, &allreduce_min_int,
                               &bcast,  &send,     &recv,    &sendrecv,  &gather,
                               &gatherv};

}  // namespace

extern "C" {

__attribute__((visibility("default"))) uint32_t imx_mpi_plugin_abi(void) {
  return IMX_MPI_PLUGIN_ABI_VERSION;
}

__attribute__((visibility("default"))) const imx_mpi_calls* imx_mpi_plugin_calls(void) {
  return &kCalls;
}
}

// The definitions have the interface's signatures (imx_dist calls them through these types).
[[maybe_unused]] constexpr imx_mpi_plugin_abi_fn imx_abi_signature = &imx_mpi_plugin_abi;
[[maybe_unused]] constexpr imx_mpi_plugin_calls_fn imx_calls_signature = &imx_mpi_plugin_calls;
