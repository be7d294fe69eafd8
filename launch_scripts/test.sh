#!/usr/bin/env bash
# Sets up (setup.sh --tests), checks that the configuration reference is the
# one the options schemas generate (nadir_config --config-reference) and the
# documentation site (mkdocs build --strict: a broken link or a page missing
# from the navigation fails), then
# runs every test suite. All tests run inside a private network
# namespace (LCM udpm and the Aravis fake camera stay on its loopback).
# Then the parsers, estimator and runtime suites run again in an
# AddressSanitizer + UndefinedBehaviorSanitizer build (build-asan/);
# NADIR_SKIP_SANITIZERS=1 skips that part. Extra arguments go to ctest.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
"$NADIR_ROOT/launch_scripts/setup.sh" --tests

echo "test: configuration reference (docs/reference/configuration.md against the options schemas)"
if ! "$NADIR_BUILD/bin/nadir_config" --config-reference | diff -u "$NADIR_ROOT/docs/reference/configuration.md" -; then
  echo "test: docs/reference/configuration.md differs from what the options schemas generate;" \
       "regenerate it with: $NADIR_BUILD/bin/nadir_config --config-reference --out $NADIR_ROOT/docs/reference/configuration.md" >&2
  exit 1
fi

echo "test: documentation site (mkdocs build --strict)"
(cd "$NADIR_ROOT" && mkdocs build --strict --quiet --site-dir "$NADIR_BUILD/site")

if [ "${NADIR_SKIP_SANITIZERS:-0}" != 1 ]; then
  asan="$NADIR_ROOT/build-asan"
  sanitized_modules="ins_bridge;vo_solver;yaw_fusion;tracker;mavlink_bridge"
  if [ ! -f "$asan/CMakeCache.txt" ]; then
    cmake -G Ninja -S "$NADIR_ROOT" -B "$asan" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNADIR_SANITIZE=ON \
      -DNADIR_MODULES="$sanitized_modules" -DNADIR_DEBUG_INFO="${NADIR_DEBUG_INFO:-lines}" >/dev/null
  elif ! grep -qxF "NADIR_MODULES:STRING=$sanitized_modules" "$asan/CMakeCache.txt"; then
    cmake -S "$NADIR_ROOT" -B "$asan" -DNADIR_MODULES="$sanitized_modules" >/dev/null  # the list grew
  fi
  sanitized_suites='nadir_test_(common|ins_bridge|vo_solver|yaw_fusion|tracker|mavlink_bridge_(codec|fuzz|logic|runner))'
  unsanitized_suites='tracker_seneca'  # real photos through SIFT: minutes under ASan, the same code as the unit tests
  # Only the suites run below (a suite's target is named as its test) and what
  # they depend on: the benchmarks, processes and tools are built in build/.
  mapfile -t suites < <(cd "$asan" && ctest -N -R "$sanitized_suites" -E "$unsanitized_suites" 2>/dev/null |
                        sed -n 's/^ *Test *#[0-9]*: //p')
  ((${#suites[@]})) || { echo "test: no ASan/UBSan suite matches in $asan" >&2; exit 1; }
  echo "test: building the ${#suites[@]} ASan/UBSan suites in $asan"
  cmake --build "$asan" -j"$(nproc)" --target "${suites[@]}" 2>&1 |
    { grep -vE '^\[ *[0-9]+(%\]|/[0-9]+\]) (Building|Linking|Built)' || true; }  # pipefail: a failed build stops here
  echo "test: ASan/UBSan run"
  # OpenCV would dlopen the OpenCL loader (ocl-icd, a dependency of libopencv-dev) from its
  # worker threads; LeakSanitizer's thread scan then crashes on that library's dynamic TLS
  # at exit (seen with the descriptor matcher's tests). nadir runs OpenCV on the CPU only.
  (cd "$asan" && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
     OPENCV_OPENCL_RUNTIME=disabled nadir_in_netns ctest --output-on-failure -j"$(nproc)" -R "$sanitized_suites" -E "$unsanitized_suites")
fi

echo "test: full suite"
cd "$NADIR_BUILD"
nadir_in_netns ctest --output-on-failure -j"$(nproc)" "$@"
