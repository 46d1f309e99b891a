# Precompiled headers (docs/architecture.md, "Build time"). A test file parses GoogleTest,
# nlohmann/json, Eigen and much of the standard library, a binding file pybind11 as well (~2.5 s
# and ~7 s of CPU a file) before a line of its own code; a precompiled header parses them once.
#
# The libraries use one too (group lib): `./al demo` builds only al-refine, mostly library code,
# and this took its build from 689 to 587 s of CPU (docs/architecture.md, "Build time"). It moves
# some of GCC's inlining decisions, so the speed claims are measured on this code.
#
# al_use_pch(<target> <group>) gives <target> the precompiled header of <group>. The first target of
# a group builds it; the others reuse it (REUSE_FROM), which GCC accepts only when the flags that
# shape a header (-fPIE/-fPIC, -f options, definitions used by the headers) match, so a group is a
# set of targets built with the same flags:
#   lib     the libraries (al_add_concern): static, position-independent, -fopenmp
#   test    the gtest suites (al_add_test_suite): executables with GoogleTest's definitions
#   python  the pybind11 module (-fPIC, -fvisibility=hidden)
# A header listed here is seen by every file of its group, so a file that forgets an #include of
# one still compiles; the AL_PCH=OFF build (cmake -DAL_PCH=OFF) checks that.
option(AL_PCH "Precompile the third-party headers of the tests and the Python module" ON)

set(AL_PCH_COMMON
    <algorithm> <array> <cmath> <cstddef> <cstdint> <filesystem> <fstream> <functional> <map>
    <memory> <optional> <span> <sstream> <stdexcept> <string> <utility> <vector>
    <nlohmann/json.hpp> <Eigen/Core>)
set(AL_PCH_test ${AL_PCH_COMMON} <gtest/gtest.h>)
set(AL_PCH_lib ${AL_PCH_COMMON})
# pybind11 first: Python.h must come before the standard headers.
set(AL_PCH_python <pybind11/pybind11.h> <pybind11/numpy.h> <pybind11/stl.h> ${AL_PCH_COMMON})

function(al_use_pch target group)
  if(NOT AL_PCH)
    return()
  endif()
  if(NOT DEFINED AL_PCH_${group})
    message(FATAL_ERROR "al_use_pch: unknown group '${group}' (lib, test, python)")
  endif()
  get_property(owner GLOBAL PROPERTY AL_PCH_OWNER_${group})
  if(owner)
    target_precompile_headers(${target} REUSE_FROM ${owner})
  else()
    target_precompile_headers(${target} PRIVATE ${AL_PCH_${group}})
    set_property(GLOBAL PROPERTY AL_PCH_OWNER_${group} ${target})
  endif()
  # (CMake adds -Winvalid-pch for GCC: a header GCC has to ignore is reported, not parsed silently.)
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    # ccache can cache clang's precompiled headers only without the embedded timestamp.
    target_compile_options(${target} PRIVATE "SHELL:-Xclang -fno-pch-timestamp")
  endif()
  # ccache (the developers' launcher, docs/architecture.md) hits on files compiled with a
  # precompiled header only with these settings (ccache manual, "Precompiled headers").
  get_target_property(launcher ${target} CXX_COMPILER_LAUNCHER)
  if(launcher MATCHES "ccache")
    set_target_properties(${target} PROPERTIES CXX_COMPILER_LAUNCHER
        "${CMAKE_COMMAND};-E;env;CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime;${launcher}")
  endif()
endfunction()
