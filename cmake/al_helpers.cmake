# al_add_concern(NAME DIRS d1 [d2...] DEPS t1 [t2...])
# A static library made of every top-level .cpp in the given folders (no recursion, so
# solver subfolders stay separate concerns). An empty concern becomes an INTERFACE library.
function(al_add_concern name)
  cmake_parse_arguments(ARG "" "" "DIRS;DEPS" ${ARGN})
  set(sources "")
  foreach(dir IN LISTS ARG_DIRS)
    file(GLOB found CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/${dir}/*.cpp)
    list(APPEND sources ${found})
  endforeach()
  if(sources)
    add_library(${name} STATIC ${sources})
    # Position-independent always: the Python module links these libraries, and a flag that
    # depended on AL_PYTHON would recompile every object when `./al test` turns it on.
    set_target_properties(${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    al_use_pch(${name} lib)
    target_include_directories(${name} PUBLIC ${PROJECT_SOURCE_DIR}/include ${PROJECT_SOURCE_DIR})
    target_link_libraries(${name} PUBLIC ${ARG_DEPS})
  else()
    add_library(${name} INTERFACE)
    target_include_directories(${name} INTERFACE ${PROJECT_SOURCE_DIR}/include ${PROJECT_SOURCE_DIR})
    target_link_libraries(${name} INTERFACE ${ARG_DEPS})
  endif()
endfunction()

# al_add_test_suite(NAME DIR DEPS ...): one gtest executable per tests/<concern> folder (with
# tests/test_data.cpp, compiled once as the object library al_test_data, tests/CMakeLists.txt).
function(al_add_test_suite name dir)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${dir}/*_test.cpp)
  if(NOT sources)
    return()
  endif()
  add_executable(${name} ${sources})
  al_use_pch(${name} test)
  # Test code at -O1 in Release (docs/architecture.md, "Build time"): a third less compile time;
  # the libraries under test are the ones compiled once with the shipping flags.
  target_compile_options(${name} PRIVATE $<$<CONFIG:Release>:-O1>)
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} al_test_data GTest::gtest_main)
  target_include_directories(${name} PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  # (No build-folder path in the flags: ccache then reuses a suite's objects in a fresh build folder.)
  target_compile_definitions(${name} PRIVATE AL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60
                       PROPERTIES ENVIRONMENT "AL_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
endfunction()
