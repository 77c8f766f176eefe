#!/usr/bin/env bash
# The sweep of scripts/sweep.sh as a Slurm job array: one array task per value, then the summary
# (sweep.tsv, sweep.png) as a job that starts after every task has ended, failed ones included.
#
#   scripts/sweep_slurm.sh [options] DECK NAME VALUE...
#   scripts/sweep_slurm.sh [options] DECK NAME --log FROM TO N | --lin FROM TO N
#
# options: those of sweep.sh (-D NAME=VALUE, -u/--uniarc BIN, -o/--out DIR, --xscale, --label, --replace,
#   --no-plot), and
#   --max-running N   at most N array tasks at a time (--array=0-M%N)
#   --sbatch ARG      passed to both sbatch calls (repeatable), e.g. --sbatch --partition=short
#                     --sbatch --time=00:30:00; sbatch's SBATCH_* environment variables work too
#
# Run it on the cluster's login node, in a folder every compute node sees (the runs write to
# DIR/sweep_<stem>_<name>/<value>/ as with sweep.sh). It writes the two job scripts slurm_array.sh and
# slurm_summary.sh into the sweep folder and prints the two job ids. The summary job depends on the
# array with afterany, because a failed run must still become a row of sweep.tsv.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

usage() { sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'; }
fail() { echo "sweep_slurm.sh: $*" >&2; exit 2; }

max_running="" xscale=auto plot=yes
sbatch_args=() sweep_args=()
while [ $# -gt 0 ]; do
  case $1 in
    -h|--help) usage; exit 0 ;;
    --max-running) [ $# -ge 2 ] || fail "--max-running needs a number"; max_running=$2; shift 2 ;;
    --sbatch) [ $# -ge 2 ] || fail "--sbatch needs an argument"; sbatch_args+=("$2"); shift 2 ;;
    --xscale) [ $# -ge 2 ] || fail "--xscale needs log or lin"; xscale=$2; shift 2 ;;
    --no-plot) plot=no; shift ;;
    --summarize|--run-one|-j|--jobs) fail "$1 is not an option of sweep_slurm.sh" ;;
    *) sweep_args+=("$1"); shift ;;
  esac
done
command -v sbatch >/dev/null 2>&1 || fail "no sbatch on PATH (this is for a Slurm cluster; scripts/sweep.sh runs here)"

# sweep.sh checks the arguments and writes the sweep folder (sweep.conf, values.txt, defines.txt)
dir=$(SWEEP_PREPARE_ONLY=1 bash "$here/sweep.sh" "${sweep_args[@]}")
dir=$(cd "$dir" && pwd)
count=$(wc -l < "$dir/values.txt")
array="0-$((count - 1))${max_running:+%$max_running}"
name=$(sed -n 's/^name=//p' "$dir/sweep.conf")
stem=$(sed -n 's/^stem=//p' "$dir/sweep.conf")
mkdir -p "$dir/slurm"

cat > "$dir/slurm_array.sh" <<EOF
#!/usr/bin/env bash
#SBATCH --job-name=uniarc_${stem}_${name}
#SBATCH --array=$array
#SBATCH --ntasks=1
#SBATCH --cpus-per-task=1
#SBATCH --output=$dir/slurm/task_%a.out
# One uniarc run: the value on line SLURM_ARRAY_TASK_ID + 1 of values.txt. The task ends with uniarc's
# exit code, so that Slurm's accounting shows the failed values too.
set -euo pipefail
value=\$(sed -n "\$((SLURM_ARRAY_TASK_ID + 1))p" "$dir/values.txt")
[ -n "\$value" ] || { echo "no value for array task \$SLURM_ARRAY_TASK_ID" >&2; exit 2; }
bash "$here/sweep.sh" --run-one "$dir" "\$value"
exit "\$(cat "$dir/\$value/exit_code")"
EOF

plot_option=""
[ "$plot" = yes ] || plot_option="--no-plot"
cat > "$dir/slurm_summary.sh" <<EOF
#!/usr/bin/env bash
#SBATCH --job-name=uniarc_${stem}_${name}_summary
#SBATCH --ntasks=1
#SBATCH --cpus-per-task=1
#SBATCH --output=$dir/slurm/summary.out
# sweep.tsv and sweep.png from whatever the array tasks left (a run that never started is failed(not_run)).
set -euo pipefail
bash "$here/sweep.sh" --summarize "$dir" --xscale $xscale $plot_option
EOF

array_job=$(sbatch --parsable "${sbatch_args[@]}" "$dir/slurm_array.sh")
array_job=${array_job%%;*}
summary_job=$(sbatch --parsable "${sbatch_args[@]}" --dependency="afterany:$array_job" "$dir/slurm_summary.sh")
summary_job=${summary_job%%;*}
echo "submitted: array job $array_job ($count runs of $stem over $name), summary job $summary_job"
echo "results: $dir/sweep.tsv when job $summary_job has run (squeue -j $array_job,$summary_job)"
