#!/usr/bin/env bash
# A rank killed mid-training: the job ends (bounded wait) with a message; resuming its last
# checkpoint with one rank gives the uninterrupted run's parameters.
set -u
mpirun=$1 test_bin=$2
run_dir=$(mktemp -d)
trap 'rm -rf "$run_dir"' EXIT
export FACETOOL_TEST_RUN_DIR=$run_dir
# Bounded: a hang would end with 124 after 240 s and fail the test.
timeout 240 "$mpirun" --allow-run-as-root --oversubscribe -np 2 "$test_bin" \
  --gtest_filter='DistributedTrain.KilledRank' >"$run_dir/out.txt" 2>&1
rc=$?
cat "$run_dir/out.txt"
if [ "$rc" -eq 124 ]; then echo "FAIL: the surviving rank hung (killed by timeout)"; exit 1; fi
if [ "$rc" -eq 0 ]; then echo "FAIL: the job succeeded although a rank was killed"; exit 1; fi
grep -qiE 'signal 9|killed|exited on signal|aborted|MPI_Allreduce failed' "$run_dir/out.txt" ||
  { echo "FAIL: no message says a rank stopped"; exit 1; }
[ -f "$run_dir/checkpoint.safetensors" ] || { echo "FAIL: no checkpoint of step 2"; exit 1; }
echo "the job stopped with exit status $rc and a message; resuming with one rank"
timeout 240 "$test_bin" --gtest_filter='DistributedTrain.ResumeWithOneRank' || exit 1
