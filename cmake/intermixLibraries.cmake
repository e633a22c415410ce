# The libraries intermix links that ship no CMake package of their own, as imported targets:
#   PkgConfig::IMX_SPNG    spng, through pkg-config
#   intermix_dep::nifti    niftiio and znz (libnifti2-dev)
#   intermix_dep::zarr_codecs  zstd and blosc (libzstd-dev, libblosc-dev): OME-Zarr chunks
#   intermix_dep::tiff     libtiff (libtiff-dev): TIFF stacks, OME-TIFF and BigTIFF volumes
#   intermix_dep::gdcm     GDCM's parser (libgdcm-dev; its CMake package on Debian 12 names
#                          tools that are not installed, so the libraries are found one by one):
#                          DSED and Common only, which do not load GDCM's tag dictionary
#   intermix_dep::gdcm_codecs  GDCM's image reader and codecs (MSFF, which loads DICT, IOD and the
#                          JPEG libraries): only the DICOM codec plugin links them
# CMakeLists.txt includes this file for the build, and the installed intermixConfig.cmake
# includes the same file, so a consumer of the package finds them the way the build did (the
# exported static libraries name these targets). It fails nothing itself: what it could not
# find is left in _imx_missing and the includer says so.
set(_imx_missing)

if(NOT TARGET PkgConfig::IMX_SPNG)
  find_package(PkgConfig QUIET)
  if(PKG_CONFIG_FOUND)
    pkg_check_modules(IMX_SPNG QUIET IMPORTED_TARGET spng)
  endif()
  if(NOT TARGET PkgConfig::IMX_SPNG)
    list(APPEND _imx_missing "spng (pkg-config module spng; Debian: libspng-dev)")
  endif()
endif()

# An INTERFACE IMPORTED target linking the libraries named, found with find_library.
function(_imx_import_libraries target package)
  if(TARGET ${target})
    return()
  endif()
  set(paths)
  set(missing)
  foreach(name IN LISTS ARGN)
    find_library(IMX_${name}_LIBRARY ${name})
    if(IMX_${name}_LIBRARY)
      list(APPEND paths "${IMX_${name}_LIBRARY}")
    else()
      list(APPEND missing lib${name})
    endif()
  endforeach()
  if(missing)
    list(JOIN missing ", " missing)
    set(_imx_missing ${_imx_missing} "${missing} (Debian: ${package})" PARENT_SCOPE)
    return()
  endif()
  add_library(${target} INTERFACE IMPORTED)
  set_target_properties(${target} PROPERTIES INTERFACE_LINK_LIBRARIES "${paths}")
endfunction()

_imx_import_libraries(intermix_dep::nifti libnifti2-dev niftiio znz)
_imx_import_libraries(intermix_dep::zarr_codecs "libzstd-dev, libblosc-dev" zstd blosc)
_imx_import_libraries(intermix_dep::tiff libtiff-dev tiff)
_imx_import_libraries(intermix_dep::gdcm libgdcm-dev gdcmDSED gdcmCommon)
_imx_import_libraries(intermix_dep::gdcm_codecs libgdcm-dev gdcmMSFF gdcmDSED gdcmIOD gdcmDICT gdcmCommon)
