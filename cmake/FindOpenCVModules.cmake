# Finds OpenCV from Debian's per-module packages (libopencv-core-dev, libopencv-imgcodecs-dev, ...),
# which ship headers under /usr/include/opencv4 and the libraries, but no CMake config or pkg-config
# file. Defines an imported target OpenCV::<module> for each requested component, and
# OpenCVModules_VERSION from opencv2/core/version.hpp.
#   find_package(OpenCVModules REQUIRED COMPONENTS core imgproc imgcodecs)
find_path(OpenCVModules_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4)

if(OpenCVModules_INCLUDE_DIR AND EXISTS "${OpenCVModules_INCLUDE_DIR}/opencv2/core/version.hpp")
  file(STRINGS "${OpenCVModules_INCLUDE_DIR}/opencv2/core/version.hpp" version_lines
       REGEX "^#define CV_VERSION_(MAJOR|MINOR|REVISION) +[0-9]+")
  foreach(part MAJOR MINOR REVISION)
    string(REGEX REPLACE ".*#define CV_VERSION_${part} +([0-9]+).*" "\\1" OpenCVModules_${part} "${version_lines}")
  endforeach()
  set(OpenCVModules_VERSION "${OpenCVModules_MAJOR}.${OpenCVModules_MINOR}.${OpenCVModules_REVISION}")
endif()

foreach(component IN LISTS OpenCVModules_FIND_COMPONENTS)
  find_library(OpenCVModules_${component}_LIBRARY opencv_${component})
  if(OpenCVModules_INCLUDE_DIR AND OpenCVModules_${component}_LIBRARY)
    set(OpenCVModules_${component}_FOUND TRUE)
    if(NOT TARGET OpenCV::${component})
      add_library(OpenCV::${component} UNKNOWN IMPORTED)
      set_target_properties(OpenCV::${component} PROPERTIES
        IMPORTED_LOCATION "${OpenCVModules_${component}_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${OpenCVModules_INCLUDE_DIR}")
    endif()
  endif()
endforeach()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenCVModules
  REQUIRED_VARS OpenCVModules_INCLUDE_DIR
  VERSION_VAR OpenCVModules_VERSION
  HANDLE_COMPONENTS)
mark_as_advanced(OpenCVModules_INCLUDE_DIR)
