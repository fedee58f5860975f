# The Python module `glassmap` (pybind11): detection and option (included before src/), and the
# module itself (glassmap_add_python_package(), called after src/ and tools/).
#
#   GLASSMAP_BUILD_PYTHON        default ON when Python 3 (interpreter, headers, NumPy) and pybind11
#                                are found; OFF in GLASSMAP_SANITIZE and GLASSMAP_ENGINE_ONLY builds
#   GLASSMAP_PYTHON_INSTALL_DIR  where `cmake --install` puts the package (default: Python3_SITEARCH
#                                when it lies under CMAKE_INSTALL_PREFIX, else
#                                lib/python3.X/site-packages under the prefix)
#
# The package is built into <build>/python/glassmap/: `PYTHONPATH=<build>/python python3 -c
# "import glassmap"`.

set(_glassmap_python_default OFF)
if(NOT GLASSMAP_SANITIZE AND NOT GLASSMAP_ENGINE_ONLY)
  # Prefer Debian's interpreter (it has python3-numpy) over a pyenv shim earlier on PATH; pass
  # -DPython3_EXECUTABLE=... to use another one.
  if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python interpreter of the glassmap module")
  endif()
  find_package(Python3 COMPONENTS Interpreter Development NumPy QUIET)
  if(Python3_FOUND)
    find_package(pybind11 CONFIG QUIET)
  endif()
  if(Python3_FOUND AND pybind11_FOUND)
    set(_glassmap_python_default ON)
  endif()
endif()
option(GLASSMAP_BUILD_PYTHON "Build the Python module glassmap (pybind11)" ${_glassmap_python_default})

if(GLASSMAP_BUILD_PYTHON)
  if(GLASSMAP_ENGINE_ONLY)
    message(FATAL_ERROR "GLASSMAP_BUILD_PYTHON needs the whole pipeline: turn GLASSMAP_ENGINE_ONLY off")
  endif()
  if(NOT Python3_FOUND OR NOT pybind11_FOUND)
    message(FATAL_ERROR "GLASSMAP_BUILD_PYTHON: needs Python 3 with headers and NumPy and pybind11 "
                        "(Debian: python3-dev python3-numpy pybind11-dev); found Python3=${Python3_FOUND} "
                        "pybind11=${pybind11_FOUND}")
  endif()
  # Static libraries linked into a shared module must be position independent.
  set(CMAKE_POSITION_INDEPENDENT_CODE ON)
  message(STATUS "Python module: ${Python3_EXECUTABLE} (${Python3_VERSION}), pybind11 ${pybind11_VERSION}")
endif()

function(glassmap_add_python_package)
  set(pkg_dir ${PROJECT_BINARY_DIR}/python/glassmap)
  file(GLOB sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/python/src/*.cpp)
  pybind11_add_module(glassmap_python MODULE ${sources})
  target_include_directories(glassmap_python PRIVATE ${PROJECT_SOURCE_DIR}/python/src)
  target_link_libraries(glassmap_python PRIVATE glassmap_pipeline glassmap_io glassmap_core
                                                nlohmann_json::nlohmann_json)
  set_target_properties(glassmap_python PROPERTIES OUTPUT_NAME _glassmap LIBRARY_OUTPUT_DIRECTORY ${pkg_dir})
  glassmap_set_warnings(glassmap_python)
  # The pure-Python part of the package, copied next to the extension at build time.
  file(GLOB py_files CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/python/glassmap/*.py)
  set(copied "")
  foreach(f ${py_files})
    get_filename_component(name ${f} NAME)
    add_custom_command(OUTPUT ${pkg_dir}/${name} COMMAND ${CMAKE_COMMAND} -E copy_if_different ${f} ${pkg_dir}/${name}
                       DEPENDS ${f} COMMENT "python/glassmap/${name}")
    list(APPEND copied ${pkg_dir}/${name})
  endforeach()
  add_custom_target(glassmap_python_files ALL DEPENDS ${copied})
  add_dependencies(glassmap_python glassmap_python_files)

  if(NOT GLASSMAP_PYTHON_INSTALL_DIR)
    set(default_dir lib/python${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}/site-packages)
    cmake_path(IS_PREFIX CMAKE_INSTALL_PREFIX "${Python3_SITEARCH}" NORMALIZE sitearch_in_prefix)
    if(Python3_SITEARCH AND sitearch_in_prefix)
      set(default_dir ${Python3_SITEARCH})
    endif()
    set(GLASSMAP_PYTHON_INSTALL_DIR ${default_dir} CACHE PATH
        "Where cmake --install puts the Python package glassmap (relative: under CMAKE_INSTALL_PREFIX)")
  endif()
  install(TARGETS glassmap_python LIBRARY DESTINATION ${GLASSMAP_PYTHON_INSTALL_DIR}/glassmap)
  install(FILES ${py_files} DESTINATION ${GLASSMAP_PYTHON_INSTALL_DIR}/glassmap)
endfunction()
