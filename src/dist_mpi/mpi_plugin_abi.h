/* The C interface of the MPI plugin (libimx_mpi.so, built from this folder): the few MPI calls
 * intermix render --distributed makes (src/dist/distributed_render.cpp). imx_dist opens the
 * plugin with dlopen when a distributed frame starts, so that Open MPI (libmpi, open-rte,
 * open-pal, hwloc, libevent, udev) is loaded only then, not at every start-up. Plain C; MPI's
 * default error handler ends the job on a failed call, so the calls return nothing. */
#ifndef IMX_MPI_PLUGIN_ABI_H
#define IMX_MPI_PLUGIN_ABI_H

#include <stddef.h>
#include <stdint.h>

/* Raised whenever a signature or struct below changes: a plugin of another version is not used. */
#define IMX_MPI_PLUGIN_ABI_VERSION 1u

#define IMX_MPI_PLUGIN_ABI_SYMBOL "imx_mpi_plugin_abi"
#define IMX_MPI_PLUGIN_CALLS_SYMBOL "imx_mpi_plugin_calls"

/* The element types of the messages, each its MPI type. */
enum imx_mpi_type {
  IMX_MPI_BYTE = 1, /* MPI_BYTE */
  IMX_MPI_CHAR,     /* MPI_CHAR */
  IMX_MPI_INT,      /* MPI_INT */
  IMX_MPI_UINT64,   /* MPI_UINT64_T */
  IMX_MPI_FLOAT,    /* MPI_FLOAT */
  IMX_MPI_DOUBLE    /* MPI_DOUBLE */
};

/* The calls, on MPI_COMM_WORLD; each is the MPI function of its name. */
struct imx_mpi_calls {
  /* MPI_Init_thread (MPI_THREAD_FUNNELED) unless MPI is initialized already (*owner then 0),
   * then this process's rank, the job's size and the number of ranks sharing this machine. */
  void (*init)(int32_t* rank, int32_t* size, int32_t* node_ranks, int32_t* owner);
  void (*finalize)(void);
  void (*barrier)(void);
  void (*abort)(int32_t code);
  /* MPI_Allreduce with MPI_MIN of one int. */
  void (*allreduce_min_int)(const int32_t* in, int32_t* out);
  void (*bcast)(void* data, int32_t count, int32_t type, int32_t root);
  void (*send)(const void* data, int32_t count, int32_t type, int32_t to, int32_t tag);
  void (*recv)(void* data, int32_t count, int32_t type, int32_t from, int32_t tag);
  void (*sendrecv)(const void* out, int32_t out_count, void* in, int32_t in_count, int32_t type,
                   int32_t partner, int32_t tag);
  void (*gather)(const void* mine, int32_t count, void* all, int32_t type, int32_t root);
  void (*gatherv)(const void* mine, int32_t count, void* all, const int32_t* counts,
                  const int32_t* displs, int32_t type, int32_t root);
};

#ifdef __cplusplus
extern "C" {
#endif

/* Returns IMX_MPI_PLUGIN_ABI_VERSION as the plugin was built. */
typedef uint32_t (*imx_mpi_plugin_abi_fn)(void);

/* The plugin's calls (static: valid until the process ends). */
typedef const struct imx_mpi_calls* (*imx_mpi_plugin_calls_fn)(void);

#ifdef __cplusplus
}
#endif

#endif
