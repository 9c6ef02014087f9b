# Common compile settings for every hrisim target: C++20, strict warnings, and no value-changing
# floating-point optimisations, no fused multiply-adds (determinism: same inputs, same bits, on
# every CPU).
function(hrisim_target_settings target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -fno-fast-math -ffp-contract=off)
  if(HRISIM_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# hrisim_module(NAME SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# One static library per module; headers live beside the sources and are included as "<module>/x.hpp".
function(hrisim_module name)
  cmake_parse_arguments(ARG "" "INCLUDE_ROOT" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(hrisim_${name} STATIC ${ARG_SOURCES})
  add_library(hrisim::${name} ALIAS hrisim_${name})
  if(NOT ARG_INCLUDE_ROOT)
    set(ARG_INCLUDE_ROOT "${PROJECT_SOURCE_DIR}/server")
  endif()
  target_include_directories(hrisim_${name} PUBLIC "${ARG_INCLUDE_ROOT}")
  target_link_libraries(hrisim_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  hrisim_target_settings(hrisim_${name})
endfunction()

# hrisim_embed_files(VAR NAMESPACE ns COMMENT text FILES file...)
# Generates a source (its path in VAR) defining, in namespace ns, `kEmbedded` — {file name, contents}
# of each file — and `kEmbeddedCount` (cmake/EmbedFiles.cmake), so the files ship inside the binary.
function(hrisim_embed_files var)
  cmake_parse_arguments(ARG "" "NAMESPACE;COMMENT" "FILES" ${ARGN})
  string(REPLACE "::" "_" stem "${ARG_NAMESPACE}")
  set(output "${CMAKE_CURRENT_BINARY_DIR}/${stem}.cpp")
  string(REPLACE ";" "$<SEMICOLON>" inputs "${ARG_FILES}")
  add_custom_command(
    OUTPUT "${output}"
    COMMAND ${CMAKE_COMMAND} "-DINPUTS=${inputs}" -DOUTPUT=${output} -DNAMESPACE=${ARG_NAMESPACE} -P ${PROJECT_SOURCE_DIR}/cmake/EmbedFiles.cmake
    DEPENDS ${ARG_FILES} ${PROJECT_SOURCE_DIR}/cmake/EmbedFiles.cmake
    COMMENT "${ARG_COMMENT}"
    VERBATIM)
  set(${var} "${output}" PARENT_SCOPE)
endfunction()
