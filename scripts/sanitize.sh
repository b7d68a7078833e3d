#!/usr/bin/env bash
# Builds the test suite with AddressSanitizer + UndefinedBehaviorSanitizer in build-asan (gcc,
# -fno-sanitize-recover=all: the first finding aborts its test) and runs a representative subset
# (only its programs are built), or builds everything and runs the tests matching the ctest -R
# pattern given.   usage: scripts/sanitize.sh [PATTERN]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${FACETOOL_ASAN_BUILD_DIR:-build-asan}
jobs=${FACETOOL_JOBS:-2}
flags="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"

# No OpenCL: PoCL compiles kernels with its own LLVM at run time and its ICD loader is not built
# with ASan; under ASan it reports its own allocations and is far too slow. The opencl backend has
# its own tests in the ordinary suite.
mkdir -p "$build"
# No Python module: an extension built with ASan cannot be loaded by the ordinary python3.
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFACETOOL_BUILD_OPENCL=OFF -DFACETOOL_BUILD_PYTHON=OFF \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_C_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="$flags" -DCMAKE_SHARED_LINKER_FLAGS="$flags" \
  -DCMAKE_MODULE_LINKER_FLAGS="$flags" > "$build/configure.log" 2>&1 ||
  { cat "$build/configure.log"; exit 1; }
# The subset: every parser (with the fuzz replays), the plugin loader and its broken plugins, the
# SH library, autograd, the cpu backend's bad-input checks, the renderer plugin, synth sample I/O
# and errors, the dataset reader, the landmark model's copy (its build step runs under the
# sanitizers too) and its trees against dlib's predictor, the landmark normal head, the EXR
# encoder, the JPEG and PNG readers and the OpenImageIO module's loading, the light's gain and solve, the
# cpu backend's fused convolutions (direct summation from a padded copy among them), inference,
# the command line and its table of bad inputs (cli_bad_input_*: every command, damaged files,
# full disks, limits, signals), and the thread pool.
subset_targets=(facetool facetool_models sh_renderer paper_network paper_losses
  good_loss second_good_loss null_create wrong_version no_entry unknown_kind old_version other_abi
  safetensors_test light_formats_test plugin_loader_test sh_tests autograd_test cpu_bad_input_test
  renderer_tests synth_io_test synth_errors_test synth_dataset_test infer_test light_cli_test
  progress_bar_test parser_errors_test parallel_for_test cpu_fused_test face_landmark_model_copy_test face_landmark_trees_test landmark_normals_test
  exr_encoding_test light_gain_test light_from_shading_test image_file_test image_file_module_test
  fuzz_replay_safetensors fuzz_replay_light_json fuzz_replay_light_text fuzz_replay_obj
  fuzz_replay_synth_sample fuzz_replay_plugin_descriptor fuzz_replay_image_file)
if [ $# -gt 0 ]; then
  cmake --build "$build" -j "$jobs"
else
  cmake --build "$build" -j "$jobs" --target "${subset_targets[@]}"
fi

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tests/sanitize/lsan.supp}
if [ $# -gt 0 ]; then
  selection=(-R "$1")
else
  # Left out: the cpu/opencl parity sweep and other opencl tests (no OpenCL here), the PyTorch
  # parity runs (Python, minutes under ASan), the Yale B benchmark test (Python only), the
  # performance test (timings only), and the
  # script tests that drive programs outside the subset (training, MPI ranks, sharding), and the
  # browser test (view_browser: LeakSanitizer's tracer crashes in facetool runs made while
  # Chromium is up; view_cli runs the same commands alone).
  # Tests of programs outside the subset show up as <program>_NOT_BUILT.
  selection=(-E "_NOT_BUILT|Parity|[Oo]pencl|ProgramCache|pytorch_parity|SynthPerformance|distributed_|eval_shards|train_cli|yaleb_benchmark|view_browser")
fi
ctest --test-dir "$build" -j "$jobs" --timeout 900 --output-on-failure "${selection[@]}"
