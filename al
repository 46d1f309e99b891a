#!/usr/bin/env bash
# One entry point for people: ./al demo | ./al test | ./al build | ./al bench [--quick]
# Each step installs what is missing and builds first, so a fresh Debian 12 machine needs nothing else.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="${AL_BUILD_DIR:-$here/build}"
jobs="$(nproc 2>/dev/null || echo 2)"

# Extra CMake flags: `./al test` builds the Python module too, for the interpreter Debian's
# python3-* packages belong to (a pyenv or venv python3 earlier in PATH may lack numpy). Turning it
# on changes no other target's flags (the libraries are always position-independent), so the
# objects `./al demo` compiled are reused.
cmake_flags=()
setup_flags=()
targets=()
build_all() {
  "$here/scripts/setup" "${setup_flags[@]}"
  cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release "${cmake_flags[@]}" >/dev/null
  cmake --build "$build" -j "$jobs" "${targets[@]}"
}

cmd="${1:-help}"
shift || true
case "$cmd" in
  build) build_all ;;
  demo)
    # Only what the demo runs: the build packages and the al-refine binary (not the tests,
    # benchmarks or Python module; `./al test` adds them to the same build folder).
    setup_flags=(--build)
    targets=(--target al-refine)
    build_all
    exec "$here/scripts/demo" "$build/al-refine" "$@"
    ;;
  test)
    cmake_flags=(-DAL_PYTHON=ON -DPython3_EXECUTABLE=/usr/bin/python3)
    build_all
    cd "$build"
    exec ctest --output-on-failure -j "$jobs" "$@"
    ;;
  bench)
    build_all
    exec "$here/bench/run" "$@"
    ;;
  *)
    echo "usage: ./al demo | test | build | bench [--quick]" >&2
    echo "  demo   install the build deps, build al-refine, run the main job on a generated scene" >&2
    echo "  test   install deps, build (with the Python module), run every test (ctest, pytest, browser)" >&2
    echo "  bench  install deps, build, run every benchmark (bench/run; --quick < 5 min) -> docs/benchmarks.md" >&2
    exit 1
    ;;
esac
