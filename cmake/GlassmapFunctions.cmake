# Shared helpers: warning flags set once, one static library per module, one test binary per module.

function(glassmap_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    # GCC 12 reports false -Wrestrict positives inside libstdc++'s std::string operator+
    # at -O2 (GCC bug 105329); it would fail -Werror on correct code.
    target_compile_options(${target} PRIVATE -Wno-restrict)
  endif()
  if(GLASSMAP_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# glassmap_add_module(<name> [DEPS <targets>...])
# Builds glassmap_<name> from every .cpp in src/<name>/; public headers in include/glassmap/<name>/.
function(glassmap_add_module name)
  cmake_parse_arguments(ARG "" "" "DEPS;PRIVATE_DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  if(NOT sources)
    message(FATAL_ERROR "module ${name} has no sources")
  endif()
  add_library(glassmap_${name} STATIC ${sources})
  add_library(glassmap::${name} ALIAS glassmap_${name})
  target_include_directories(glassmap_${name}
    PUBLIC ${PROJECT_SOURCE_DIR}/include
    PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  target_link_libraries(glassmap_${name} PUBLIC ${ARG_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  glassmap_set_warnings(glassmap_${name})
endfunction()

# glassmap_add_test(<name> SOURCES <files>... LIBS <targets>...)
function(glassmap_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main)
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/tests)
  target_compile_definitions(${name} PRIVATE
    GLASSMAP_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    GLASSMAP_BINARY_DIR="${PROJECT_BINARY_DIR}")
  glassmap_set_warnings(${name})
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS ${name})
endfunction()

# glassmap_forbid_links(TARGETS <targets>... FORBIDDEN <targets>...)
# Fails the configure step when the link interface of a target (followed through every library
# it links, PRIVATE deps of static libraries included) reaches a forbidden target: the stages
# that a localizer or a mapper embeds must not drag in GDAL or Cairo.
function(glassmap_forbid_links)
  cmake_parse_arguments(ARG "" "" "TARGETS;FORBIDDEN" ${ARGN})
  foreach(root ${ARG_TARGETS})
    set(queue ${root})
    set(seen "")
    while(queue)
      list(POP_FRONT queue t)
      if(t IN_LIST seen OR NOT TARGET ${t})
        continue()
      endif()
      list(APPEND seen ${t})
      get_target_property(libs ${t} INTERFACE_LINK_LIBRARIES)
      if(NOT libs)
        continue()
      endif()
      foreach(lib ${libs})
        string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" lib "${lib}")
        if(lib IN_LIST ARG_FORBIDDEN)
          message(FATAL_ERROR "${root} links ${lib} (through ${t}); it must not")
        endif()
        list(APPEND queue ${lib})
      endforeach()
    endwhile()
  endforeach()
endfunction()
