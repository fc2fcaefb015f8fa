#!/usr/bin/env bash
# The whole test suite again, built with AddressSanitizer and UndefinedBehaviorSanitizer (-DUVR_SANITIZE=ON) in
# build-asan/, run with ctest. Any sanitizer report fails the test that triggers it (UBSan does not recover; ASan and
# LeakSanitizer abort at the first report). .ci/run calls it after the normal suite; docs/robustness.md has the times.
# UVR_JOBS sets the parallelism of the build and of ctest (default: the number of cores).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
jobs="${UVR_JOBS:-$(nproc)}"
data="${UVR_DATA_DIR:-$PWD/data}"
# The test programs' own code is not instrumented (the sanitizers check uvr's code, which the tests call), so this
# build links the normal build's test objects rather than compiling them again (tests/CMakeLists.txt): build/ first,
# configured as scripts/test.sh configures it (nothing to do after scripts/test.sh).
cmake -S . -B build -G Ninja -DUVR_DATA_DIR="$data" >/dev/null
bash scripts/build.sh
# Built with clang, the second compiler of Debian 12 (install-deps.sh), which compiles instrumented code in about half
# gcc's time (docs/robustness.md, "Sanitizers in CI").
cmake -S . -B build-asan -G Ninja -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DUVR_SANITIZE=ON -DUVR_PYTHON=OFF -DUVR_DATA_DIR="$data" \
  -DUVR_TEST_OBJECTS_FROM="$PWD/build" >/dev/null
cmake --build build-asan -j "$jobs"
# Mesa (OSMesa, EGL, llvmpipe's JIT) keeps allocations of its own alive past exit (OSMesaMakeCurrent's dispatch
# tables, glapi state) even when uvr destroys its contexts; LeakSanitizer is told to ignore leaks whose stack is in
# Mesa's libraries, and only those. Likewise netCDF and HDF5 (the Exodus II reader's): libhdf5 keeps a global
# allocation, and libnetcdf leaks what it allocated when it fails to open a damaged netCDF-4 file (docs/formats.md).
# Everything else (uvr, the other libraries) is checked.
cat >build-asan/lsan-suppressions.txt <<'SUPP'
leak:libOSMesa.so
leak:libEGL_mesa.so
leak:libgallium
leak:libglapi.so
leak:libLLVM
leak:libnetcdf.so
leak:libhdf5
SUPP
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$PWD/build-asan/lsan-suppressions.txt:print_suppressions=0}"
# intercept_tls_get_addr=0: up to LLVM 16 the runtime's __tls_get_addr interceptor can take a malloc'd block for a
# pre-2.25 glibc TLS header when it lands on a certain page offset, and LeakSanitizer's tracer then crashes at exit
# ("Tracer caught signal 11", no leak reported); dynamic TLS is what OSMesa, opened with dlopen, uses for its current
# context. Leaks are still found; only pointers held in dynamic TLS are no longer roots (Mesa's, suppressed above).
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:check_initialization_order=1:strict_string_checks=1:intercept_tls_get_addr=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
cd build-asan
# The tests whose name says EGL run with LeakSanitizer off (tests/CMakeLists.txt says why).
ctest --output-on-failure -j "$jobs"
