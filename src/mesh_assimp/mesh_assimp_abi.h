/* The C interface of the mesh plugin (libimx_mesh_assimp.so, built from this folder): assimp's
 * importers for the mesh formats intermix does not parse itself (OBJ, STL, OFF, glTF). imx_io
 * opens the plugin with dlopen on the first such file (io/mesh/mesh_assimp_plugin.cpp), so that
 * assimp, draco and minizip are not loaded at every start-up. Plain C: paths, counts, buffers
 * and an error string; no C++ type or exception crosses it. */
#ifndef IMX_MESH_ASSIMP_ABI_H
#define IMX_MESH_ASSIMP_ABI_H

#include <stddef.h>
#include <stdint.h>

/* Raised whenever a signature or struct below changes: a plugin of another version is not used. */
#define IMX_MESH_ASSIMP_ABI_VERSION 1u

#define IMX_MESH_ASSIMP_ABI_SYMBOL "imx_mesh_assimp_abi"
#define IMX_MESH_ASSIMP_READ_SYMBOL "imx_mesh_assimp_read"
#define IMX_MESH_ASSIMP_COPY_SYMBOL "imx_mesh_assimp_copy"
#define IMX_MESH_ASSIMP_CLOSE_SYMBOL "imx_mesh_assimp_close"

/* imx_mesh_assimp_read's results. */
enum imx_mesh_assimp_status {
  IMX_MESH_ASSIMP_OK = 0,
  IMX_MESH_ASSIMP_FAILED = 1,       /* `error` says why (without the file's name) */
  IMX_MESH_ASSIMP_OUT_OF_MEMORY = 2 /* an allocation failed */
};

/* What an imported mesh holds: every mesh of the file's node tree, in file units. */
struct imx_mesh_assimp_counts {
  uint64_t vertices;
  uint64_t triangles;
  int32_t normals; /* 1 when every mesh has normals */
  int32_t colors;  /* 1 when every mesh has vertex colours */
};

#ifdef __cplusplus
extern "C" {
#endif

/* Returns IMX_MESH_ASSIMP_ABI_VERSION as the plugin was built. */
typedef uint32_t (*imx_mesh_assimp_abi_fn)(void);

/* Asked before assimp opens any file but the mesh itself (an OBJ's mtllib, glTF buffers):
 * returns 0 when `path` may be read, else non-zero with a NUL-terminated reason in `error`. */
typedef int32_t (*imx_mesh_assimp_allow_fn)(void* context, const char* path, char* error,
                                            size_t error_size);

/* Imports the mesh file `path` (triangulated, identical vertices joined, points and lines
 * dropped): returns IMX_MESH_ASSIMP_OK with *scene (for copy and close) and *counts set, or
 * another status with a NUL-terminated message in `error` (error_size bytes). Vertex colours are
 * sRGB-decoded when srgb_colors is non-zero, else clamped to [0, 1]. */
typedef int32_t (*imx_mesh_assimp_read_fn)(const char* path, int32_t srgb_colors,
                                           imx_mesh_assimp_allow_fn allow, void* context,
                                           void** scene, struct imx_mesh_assimp_counts* counts,
                                           char* error, size_t error_size);

/* Writes the imported mesh: counts.vertices xyz positions, unit normals (zero where assimp
 * gave none that is finite; skipped when `normals` is null) and linear RGB colours (skipped when
 * null), and counts.triangles vertex-index triples, in the node tree's order with each node's
 * transform applied. Returns IMX_MESH_ASSIMP_OK, or IMX_MESH_ASSIMP_OUT_OF_MEMORY. */
typedef int32_t (*imx_mesh_assimp_copy_fn)(void* scene, float* positions, float* normals,
                                        float* colors, uint32_t* triangles);

/* Frees what imx_mesh_assimp_read returned. */
typedef void (*imx_mesh_assimp_close_fn)(void* scene);

#ifdef __cplusplus
}
#endif

#endif
