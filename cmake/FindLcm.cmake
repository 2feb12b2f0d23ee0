# Debian's LCM 1.3.1 ships no CMake package and its pkg-config file needs glib headers:
# find the header and library directly and expose an imported target lcm::lcm.
find_path(LCM_INCLUDE_DIR lcm/lcm-cpp.hpp)
find_library(LCM_LIBRARY lcm)
find_program(LCM_GEN_EXECUTABLE lcm-gen)
if(NOT LCM_INCLUDE_DIR OR NOT LCM_LIBRARY OR NOT LCM_GEN_EXECUTABLE)
  message(FATAL_ERROR "LCM not found (need liblcm-dev and liblcm-bin): run deploy/install-deps.sh")
endif()
add_library(lcm::lcm UNKNOWN IMPORTED)
set_target_properties(lcm::lcm PROPERTIES
  IMPORTED_LOCATION ${LCM_LIBRARY}
  INTERFACE_INCLUDE_DIRECTORIES ${LCM_INCLUDE_DIR})
find_file(LCM_JAR lcm.jar PATHS /usr/share/java /usr/local/share/java)
