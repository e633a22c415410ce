# Whether the Python package (python/) is built: IMX_PYTHON on, not a sanitizer or fuzz build, and
# pybind11 with the Python interpreter and headers found. Debian's /usr/bin/python3 is preferred
# over any other python3 on PATH (a pyenv or venv interpreter without numpy): pass
# -DPython_EXECUTABLE=... to choose another. Sets IMX_PYTHON_FOUND, and makes the libraries
# position-independent so that the extension module can link them.
set(IMX_PYTHON_FOUND OFF)
if(NOT IMX_PYTHON)
  message(STATUS "Python package: off (IMX_PYTHON=OFF)")
elseif(IMX_SANITIZE OR IMX_FUZZ)
  message(STATUS "Python package: skipped in a sanitizer or fuzz build (IMX_SANITIZE, IMX_FUZZ)")
else()
  if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The Python the package is built for")
  endif()
  set(PYBIND11_FINDPYTHON ON)
  find_package(Python 3.8 COMPONENTS Interpreter Development.Module)
  if(Python_FOUND)
    find_package(pybind11 2.6 CONFIG QUIET)
  endif()
  if(Python_FOUND AND pybind11_FOUND)
    set(IMX_PYTHON_FOUND ON)
    # A shared module links the static libraries: they must be PIC. Without semantic
    # interposition the code is what -fPIE gives the program (calls within a library inline).
    set(CMAKE_POSITION_INDEPENDENT_CODE ON)
    add_compile_options(-fno-semantic-interposition)
    message(STATUS "Python package: built for ${Python_EXECUTABLE} (Python ${Python_VERSION}, "
                   "pybind11 ${pybind11_VERSION})")
  else()
    message(STATUS "Python package: skipped, pybind11 or the Python headers were not found "
                   "(apt-get install pybind11-dev python3-dev, or -DIMX_PYTHON=OFF to silence this)")
  endif()
endif()
