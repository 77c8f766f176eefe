#!/usr/bin/env bash
# Test of scripts/sweep_slurm.sh without Slurm: a fake sbatch (fake_slurm/sbatch) runs each job at
# once, one array index after the other. The array must have one task per value, the summary job must
# depend on it with afterany (a failed value is still a row), and sweep.tsv must be what sweep.sh
# writes: here k = 0 (ok) and k = bad (failed(2)) on ex. 1 with n = 20.
#   test_sweep_slurm.sh UNIARC WORKDIR
set -euo pipefail
uniarc=$1 work=$2
here=$(cd "$(dirname "$0")" && pwd)
source_dir=$(cd "$here/../.." && pwd)
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*"; exit 1; }
export PATH="$here/fake_slurm:$PATH" FAKE_SBATCH_LOG=$PWD/sbatch.log
bash "$source_dir/scripts/sweep_slurm.sh" "$source_dir/input/ring_rigid_cavity.inp" k 0 bad -D n=20 \
  --uniarc "$uniarc" --no-plot --max-running 4 --sbatch --time=00:10:00
cat sbatch.log
dir=sweep_ring_rigid_cavity_k
grep -q '^#SBATCH --array=0-1%4$' "$dir/slurm_array.sh" || fail "array line: $(grep array "$dir/slurm_array.sh")"
array_job=$(sed -n 1p fake_sbatch.jobs)
grep -q -- "--time=00:10:00 --dependency=afterany:$array_job .*slurm_summary.sh" sbatch.log \
  || fail "the summary was not submitted with afterany on the array job $array_job"
grep -q "task 1 of job $array_job: exit 2" sbatch.log || fail "the task of k = bad did not end with exit 2"
[ -f "$dir/sweep.tsv" ] || fail "no sweep.tsv"
cat "$dir/sweep.tsv"
[ "$(cut -f1,6 "$dir/sweep.tsv" | tr '\t\n' ' ')" = "value status 0 ok bad failed(2) " ] \
  || fail "sweep.tsv rows: $(cut -f1,6 "$dir/sweep.tsv" | tr '\t\n' ' ')"
echo ok
