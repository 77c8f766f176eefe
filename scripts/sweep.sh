#!/usr/bin/env bash
# One uniarc run per value of a deck parameter, in parallel, then a summary table and a plot.
#
#   scripts/sweep.sh [options] DECK NAME VALUE...
#   scripts/sweep.sh [options] DECK NAME --log FROM TO N     (N values, geometric, FROM..TO)
#   scripts/sweep.sh [options] DECK NAME --lin FROM TO N     (N values, evenly spaced)
#
# options (anywhere on the line):
#   -D NAME=VALUE   passed to every run (e.g. -D n=50); repeatable
#   -u, --uniarc BIN  the uniarc program (default: $UNIARC, else build/uniarc of this source tree)
#   -o, --out DIR   where the sweep folder goes (default: .)
#   -j, --jobs N    runs at a time (default: all cores, nproc)
#   --xscale log|lin  x axis of the plot (default: log when the positive values span a decade)
#   --label VALUE=TEXT  what a value means, for the plot (repeatable): e.g. --label 0=rigid for
#                   ring_rigid_cavity.inp, where k = 0 is the rigid cavity; a labelled value is drawn
#                   as a horizontal line "TEXT (NAME = VALUE)", never as a point of the curve
#   --replace       the sweep folder exists already: delete it first (without this, refuse)
#   --no-plot       no PNG (gnuplot not needed)
#   --summarize DIR  only (re)write DIR/sweep.tsv and DIR/sweep.png from finished runs
#
# Each run goes to DIR/sweep_<stem>_<name>/<value>/ (uniarc's STEM.path, STEM.crit, STEM.shape, the
# run's stderr in uniarc.log and its exit code in exit_code). sweep.tsv has one row per value, in the
# order given, failed runs included: value, the first limit_max load of STEM.crit, the tracked columns
# there, the contact extent there (s_contact_1, s_contact_2 of the path interpolated at the event's
# fractional step) and the status: ok, no_limit (the run ended without a limit point) or failed(N)
# (uniarc's exit code N; what the run traced is still summarised). Numbers missing are `nan`.
# sweep.png plots the first limit load against the value (log axis when the positive values span a
# decade or more); labelled values, and on a log axis values <= 0, are drawn as horizontal lines with
# their label, never joined to the curve. A sweep folder that exists already (an earlier sweep, whose value folders
# would mix with these) is refused, exit 2, unless --replace is given.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")

usage() { sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'; }
fail() { echo "sweep.sh: $*" >&2; exit 2; }

# --- the summary: sweep.tsv and sweep.png of a finished sweep folder --------------------------------
summarize() {
  local dir=$1 xscale=$2 plot=$3
  [ -f "$dir/sweep.conf" ] || fail "$dir: not a sweep folder (no sweep.conf)"
  PYTHONPATH="$here" python3 - "$dir" <<'PYTHON'
import os, sys
from uniarc_table import Table

directory = sys.argv[1]
conf = dict(line.rstrip('\n').split('=', 1) for line in open(os.path.join(directory, 'sweep.conf')))
stem, name = conf['stem'], conf['name']
values = [v for v in open(os.path.join(directory, 'values.txt')).read().split('\n') if v]


def table(path):
    """Column names and numeric rows of a uniarc path file (docs/contracts.md)."""
    try:
        data = Table(path)
    except ValueError:
        return [], []
    return data.names, [[float(x) for x in row] for row in data.rows]


def events(path):
    """Column names after `kind` and the (kind, numbers) rows of a STEM.crit file."""
    try:
        data = Table(path)
    except ValueError:
        return [], []
    return data.names[1:], [(row[0], [float(x) for x in row[1:]]) for row in data.rows]


def at_step(names, rows, step, column):
    """Path column at a fractional step: linear between the rows that bracket it."""
    index, steps = names.index(column), [row[0] for row in rows]
    for a, b in zip(rows, rows[1:]):
        if a[0] <= step <= b[0]:
            t = (step - a[0]) / (b[0] - a[0]) if b[0] > a[0] else 0.0
            return a[index] + t * (b[index] - a[index])
    return rows[-1][index] if rows and abs(steps[-1] - step) < 1e-12 else float('nan')


results, tracks = [], None
for value in values:
    run = os.path.join(directory, value)
    try:
        code = int(open(os.path.join(run, 'exit_code')).read().strip())
    except (OSError, ValueError):
        code = None
    path_file, crit_file = (os.path.join(run, stem + ext) for ext in ('.path', '.crit'))
    limit = None
    if os.path.isfile(crit_file) and os.path.isfile(path_file):
        crit_names, crit_rows = events(crit_file)
        path_names, path_rows = table(path_file)
        if tracks is None:
            tracks = crit_names[2:]
        first = next((numbers for kind, numbers in crit_rows if kind == 'limit_max'), None)
        if first is not None:
            step = first[crit_names.index('step')]
            contact = [at_step(path_names, path_rows, step, c) if c in path_names and path_rows
                       else float('nan') for c in ('s_contact_1', 's_contact_2')]
            limit = [first[crit_names.index('lambda')]] + first[2:] + contact
    if code is None:
        status = 'failed(not_run)'
    elif code != 0:
        status = f'failed({code})'
    elif limit is None:
        status = 'no_limit'
    else:
        status = 'ok'
    results.append((value, limit, status))

tracks = tracks or []
header = ['value', 'lambda_limit'] + tracks + ['s_contact_1', 's_contact_2', 'status']
with open(os.path.join(directory, 'sweep.tsv'), 'w') as out:
    out.write('\t'.join(header) + '\n')
    for value, limit, status in results:
        numbers = limit if limit is not None and len(limit) == len(header) - 2 else [float('nan')] * (len(header) - 2)
        out.write('\t'.join([value] + [f'{x:.10g}' for x in numbers] + [status]) + '\n')
bad = [f'{v} {s}' for v, _, s in results if s != 'ok']
print(f'{directory}/sweep.tsv: {len(results)} runs' + (f'; not ok: {", ".join(bad)}' if bad else ', all ok'))
PYTHON
  if [ "$plot" = yes ]; then
    if command -v gnuplot >/dev/null 2>&1; then
      plot_summary "$dir" "$xscale"
    else
      echo "sweep.sh: gnuplot not found, no sweep.png (scripts/install_deps.sh installs it)" >&2
    fi
  fi
}

plot_summary() {
  local dir=$1 xscale=$2
  python3 - "$dir" "$xscale" <<'PYTHON' | gnuplot
import math, os, sys

directory, xscale = sys.argv[1], sys.argv[2]
conf = dict(line.rstrip('\n').split('=', 1) for line in open(os.path.join(directory, 'sweep.conf')))
labels_file = os.path.join(directory, 'labels.txt')
labels = dict(line.rstrip('\n').split('=', 1) for line in open(labels_file) if '=' in line) \
    if os.path.isfile(labels_file) else {}
lines = open(os.path.join(directory, 'sweep.tsv')).read().splitlines()
rows = [line.split('\t') for line in lines[1:] if line]
finite = []
for row in rows:
    try:
        value, load = float(row[0]), float(row[1])
    except ValueError:
        continue
    if math.isfinite(load):
        finite.append((row[0], value, load))
name = conf['name']
# a labelled value (e.g. k = 0: the rigid cavity) or one <= 0 on a log axis is a level, not a point
curve = sorted((v, l) for text, v, l in finite if text not in labels and (v > 0 or xscale == 'lin'))
if xscale == 'auto':
    xs = [v for v, _ in curve if v > 0]
    xscale = 'log' if xs and max(xs) >= 10 * min(xs) else 'lin'
if xscale == 'log':
    curve = [(v, l) for v, l in curve if v > 0]
levels = [(labels.get(text, ''), text, l) for text, v, l in finite if (v, l) not in curve]
without = [f'{row[0]} ({row[-1]})' for row in rows if row[-1] != 'ok']
print('set terminal pngcairo size 900,600 enhanced font "Sans,11"')
print(f'set output "{os.path.join(directory, "sweep.png")}"')
print(f'set title "{conf["stem"]}: first limit load against {name}" noenhanced')
print(f'set xlabel "{name}" noenhanced' + (' offset 0,-0.3' if xscale == 'log' else ''))
print('set ylabel "first limit load {/Symbol l}_{lim}"')
print('set grid')
print('set key bottom right box opaque')
if xscale == 'log':
    print('set logscale x')
    print('set format x "10^{%T}"')
if curve:
    xs = [v for v, _ in curve]
    low, high = min(xs), max(xs)
    if xscale == 'log':
        print(f'set xrange [{low / 2!r}:{high * 2!r}]')
    else:
        pad = 0.05 * (high - low) if high > low else max(abs(high), 1.0)
        print(f'set xrange [{low - pad!r}:{high + pad!r}]')
ys = [l for _, _, l in finite]
if ys:
    span = max(max(ys) - min(ys), 0.05 * abs(max(ys)), 1e-12)
    print(f'set yrange [{min(ys) - 0.08 * span!r}:{max(ys) + 0.15 * span!r}]')
if without:
    print(f'set label 1 "no limit point or failed: {", ".join(without)}" at graph 0.02, graph 0.95 '
          'left front noenhanced')
print('$sweep << EOD')
for v, l in curve:
    print(f'{v!r} {l!r}')
print('EOD')
plots = []
if curve:
    plots.append('$sweep using 1:2 with linespoints lw 2 pt 7 ps 1.3 lc rgb "#1f4e9c" title "uniarc" noenhanced')
level_colours = ['#b22222', '#228b22', '#6a3d9a', '#ff8c00']
for k, (label, text, l) in enumerate(levels):
    title = f'{label} ({name} = {text}): {l:.4g}' if label else f'{name} = {text}: {l:.4g}'
    plots.append(f'{l!r} with lines dt 2 lw 2 lc rgb "{level_colours[k % len(level_colours)]}" '
                 f'title "{title}" noenhanced')
if not plots:
    print('set label 2 "no limit point in any run" at graph 0.5, graph 0.5 center')
    print('set xrange [0:1]; set yrange [0:1]')
    plots.append('NaN notitle')
if levels and not curve:
    print('set xrange [0.1:10]' if xscale == 'log' else 'set xrange [-1:1]')
print('plot ' + ', \\\n     '.join(plots))
PYTHON
  echo "$dir/sweep.png"
}

# --- one run (called through xargs, and by the Slurm array task of sweep_slurm.sh) ------------------
run_one() {
  local dir=$1 value=$2
  # shellcheck disable=SC1091
  local uniarc deck name stem
  uniarc=$(sed -n 's/^uniarc=//p' "$dir/sweep.conf")
  deck=$(sed -n 's/^deck=//p' "$dir/sweep.conf")
  name=$(sed -n 's/^name=//p' "$dir/sweep.conf")
  stem=$(sed -n 's/^stem=//p' "$dir/sweep.conf")
  local -a defines=()
  while IFS= read -r d; do [ -n "$d" ] && defines+=(-D "$d"); done < "$dir/defines.txt"
  local out="$dir/$value"
  rm -rf "$out"
  mkdir -p "$out"
  local code=0
  "$uniarc" "$deck" -o "$out" -q "${defines[@]}" -D "$name=$value" >"$out/uniarc.log" 2>&1 || code=$?
  echo "$code" > "$out/exit_code"
  echo "$name = $value: exit $code" >&2
  return 0
}

# --- command line -------------------------------------------------------------------------------------
main() {
  local uniarc=${UNIARC:-$root/build/uniarc} outroot=. jobs="" xscale=auto plot=yes summarize_only="" replace=no
  local -a defines=() positional=() range=() labels=()
  while [ $# -gt 0 ]; do
    case $1 in
      -h|--help) usage; exit 0 ;;
      -D) [ $# -ge 2 ] || fail "-D needs NAME=VALUE"; defines+=("$2"); shift 2 ;;
      -D*) defines+=("${1#-D}"); shift ;;
      -u|--uniarc) [ $# -ge 2 ] || fail "$1 needs a path"; uniarc=$2; shift 2 ;;
      -o|--out) [ $# -ge 2 ] || fail "$1 needs a folder"; outroot=$2; shift 2 ;;
      -j|--jobs) [ $# -ge 2 ] || fail "$1 needs a number"; jobs=$2; shift 2 ;;
      --xscale) [ $# -ge 2 ] || fail "--xscale needs log or lin"; xscale=$2; shift 2 ;;
      --no-plot) plot=no; shift ;;
      --replace) replace=yes; shift ;;
      --label) [ $# -ge 2 ] || fail "--label needs VALUE=TEXT"; [[ $2 == ?*=?* ]] || fail "--label $2: expected VALUE=TEXT"
               labels+=("$2"); shift 2 ;;
      --summarize) [ $# -ge 2 ] || fail "--summarize needs a sweep folder"; summarize_only=$2; shift 2 ;;
      --run-one) run_one "$2" "$3"; exit 0 ;;
      --log|--lin) [ $# -ge 4 ] || fail "$1 needs FROM TO N"; range=("$1" "$2" "$3" "$4"); shift 4 ;;
      --) shift; positional+=("$@"); break ;;
      *) positional+=("$1"); shift ;;
    esac
  done
  case $xscale in auto|log|lin) ;; *) fail "--xscale must be log or lin" ;; esac
  if [ -n "$summarize_only" ]; then
    summarize "$summarize_only" "$xscale" "$plot"
    exit 0
  fi
  [ ${#positional[@]} -ge 2 ] || { usage >&2; exit 2; }
  local deck=${positional[0]} name=${positional[1]}
  local -a values=("${positional[@]:2}")
  if [ ${#range[@]} -gt 0 ]; then
    mapfile -t generated < <(python3 - "${range[@]}" <<'PYTHON'
import sys
kind, low, high, count = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
if count < 1 or (kind == '--log' and (low <= 0 or high <= 0)):
    sys.exit('sweep.sh: --log needs positive FROM and TO, and N >= 1')
for i in range(count):
    t = i / (count - 1) if count > 1 else 0.0
    print(f'{low * (high / low) ** t if kind == "--log" else low + t * (high - low):.6g}')
PYTHON
    ) || exit 2
    values+=("${generated[@]}")
  fi
  [ ${#values[@]} -ge 1 ] || fail "no values for $name"
  [ -f "$deck" ] || fail "$deck: no such deck"
  [ -x "$uniarc" ] || fail "$uniarc: no uniarc program (build it, or give --uniarc / UNIARC)"
  [[ $name =~ ^[A-Za-z_][A-Za-z0-9_]*$ ]] || fail "$name: not a parameter name"
  local v seen=" "
  for v in "${values[@]}"; do
    [[ -n $v && $v != */* && $v != .* && $v != *[[:space:]]* ]] || fail "'$v': a value must be usable as a folder name"
    [[ $seen != *" $v "* ]] || fail "value $v given twice"
    seen+="$v "
  done
  local stem dir
  stem=$(basename "$deck"); stem=${stem%.*}
  dir=$outroot/sweep_${stem}_$name
  # value folders of an earlier sweep would mix with these runs in sweep.tsv and the plots
  if [ -e "$dir" ] && [ -n "$(ls -A "$dir" 2>/dev/null)" ]; then
    [ "$replace" = yes ] || fail "$dir exists (an earlier sweep): remove it, give --replace to delete it first, or -o another folder"
    [ -f "$dir/sweep.conf" ] || fail "$dir is not a sweep folder (no sweep.conf): not deleted, even with --replace"
    rm -rf "$dir"
  fi
  mkdir -p "$dir"
  # absolute paths, so that the runs (and the Slurm tasks) do not depend on the working directory
  {
    echo "deck=$(cd "$(dirname "$deck")" && pwd)/$(basename "$deck")"
    echo "uniarc=$(cd "$(dirname "$uniarc")" && pwd)/$(basename "$uniarc")"
    echo "name=$name"
    echo "stem=$stem"
  } > "$dir/sweep.conf"
  printf '%s\n' "${defines[@]}" | sed '/^$/d' > "$dir/defines.txt"
  printf '%s\n' "${values[@]}" > "$dir/values.txt"
  printf '%s\n' "${labels[@]}" | sed '/^$/d' > "$dir/labels.txt"
  if [ "${SWEEP_PREPARE_ONLY:-}" = 1 ]; then echo "$dir"; return 0; fi
  jobs=${jobs:-$(nproc)}
  echo "sweep.sh: ${#values[@]} runs of $stem over $name, $jobs at a time, in $dir" >&2
  printf '%s\0' "${values[@]}" | xargs -0 -n 1 -P "$jobs" bash "${BASH_SOURCE[0]}" --run-one "$dir"
  summarize "$dir" "$xscale" "$plot"
}

main "$@"
