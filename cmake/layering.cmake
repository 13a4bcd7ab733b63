# The one-way dependency of cleave's folders, checked when CMake configures.
#
# cleave_check_layer(<folder> [ALLOWS <folder>...]) reads every .hpp/.cpp of <folder> and
# fails the configuration when one of them includes a header of another cleave folder that
# is not in ALLOWS (list the whole transitive set: a folder may include what its allowed
# folders' headers include). Includes without a folder (the file's neighbours), of
# third-party libraries (<...>) and of generated headers are not judged.
#
# The same file runs as a script, which is how the test of the check itself calls it:
#   cmake -DROOT=<tree> -DFOLDER=<folder> "-DALLOWS=a;b" -P cmake/layering.cmake

set(CLEAVE_LAYER_FOLDERS
  geometry physics/bonds physics/dem physics/lattice physics/transgranular validation
  io sim parallel app python)

function(cleave_check_layer folder)
  cmake_parse_arguments(L "" "ROOT" "ALLOWS" ${ARGN})
  if(NOT L_ROOT)
    set(L_ROOT "${PROJECT_SOURCE_DIR}")
  endif()
  file(GLOB files "${L_ROOT}/${folder}/*.hpp" "${L_ROOT}/${folder}/*.cpp")
  set(bad "")
  foreach(f IN LISTS files)
    file(STRINGS "${f}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
    foreach(line IN LISTS lines)
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\".*$" "\\1" inc "${line}")
      get_filename_component(dir "${inc}" DIRECTORY)
      if(dir STREQUAL "" OR dir STREQUAL folder)
        continue()
      endif()
      list(FIND CLEAVE_LAYER_FOLDERS "${dir}" known)
      list(FIND L_ALLOWS "${dir}" allowed)
      if(known GREATER -1 AND allowed EQUAL -1)
        file(RELATIVE_PATH rel "${L_ROOT}" "${f}")
        string(APPEND bad "\n  ${rel} includes \"${inc}\"")
      endif()
    endforeach()
  endforeach()
  if(bad)
    string(REPLACE ";" ", " allows "${L_ALLOWS}")
    if(NOT allows)
      set(allows "nothing of cleave's")
    endif()
    message(FATAL_ERROR "layering: ${folder}/ may include only ${allows}; but${bad}\n"
                        "(the folders and what each may use: cmake/layering.cmake, docs/ARCHITECTURE.md)")
  endif()
endfunction()

if(CMAKE_SCRIPT_MODE_FILE AND FOLDER)
  cleave_check_layer("${FOLDER}" ROOT "${ROOT}" ALLOWS ${ALLOWS})
endif()
