#!/usr/bin/env bash
# Test of the tables' format (docs/contracts.md) with the readers users have: the one-liners of
# README.md for numpy (genfromtxt(names=True)), pandas (read_csv(sep=r'\s+', comment='#')) and gnuplot
# (columns by name, columnheader), on a real run of ex. 2 with -D values and --csv. Each reader must
# find every column by name with the numbers of the file, the counts as integers, and skip the
# provenance lines; the CSV twins must give pandas (read_csv(comment='#')) and Python's csv module the
# same table. numpy and pandas come from scripts/install_deps.sh (Debian's python3-numpy,
# python3-pandas); gnuplot too.
#   test_readers.sh UNIARC WORKDIR
set -euo pipefail
uniarc=$1 work=$2
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*"; exit 1; }

python=""
for candidate in python3 /usr/bin/python3; do
  if command -v "$candidate" >/dev/null 2>&1 && "$candidate" -c 'import numpy, pandas' 2>/dev/null; then
    python=$candidate; break
  fi
done
[ -n "$python" ] || fail "no python3 with numpy and pandas (scripts/install_deps.sh installs python3-numpy, python3-pandas)"
command -v gnuplot >/dev/null 2>&1 || fail "no gnuplot (scripts/install_deps.sh installs gnuplot-nox)"

deck=$source_dir/input/arch_foundation_below.inp
SOURCE_DATE_EPOCH=1764558245 "$uniarc" "$deck" -o out -D n=10 -D 'k = 1e4' --csv -q
stem=out/arch_foundation_below
for ext in path crit shape surface; do
  [ -f "$stem.$ext" ] && [ -f "$stem.$ext.csv" ] || fail "$stem.$ext or its .csv twin not written"
done
# the provenance lines, SOURCE_DATE_EPOCH giving the time (2025-12-01T03:04:05Z)
expected=$(printf '# uniarc %s\n# deck: %s\n# defines: n=10 k=1e4\n# utc: 2025-12-01T03:04:05Z' \
  "$("$uniarc" --version | sed 's/^uniarc //')" "$deck")
[ "$(sed -n 2,5p "$stem.path")" = "$expected" ] || fail "provenance lines: $(sed -n 2,5p "$stem.path")"

# gnuplot: columns by name (the first line), the '#' lines skipped, and columnheader as key titles
rows=$(grep -c -v -e '^#' -e '^$' "$stem.path"); rows=$((rows - 1))
gnuplot_out=$(gnuplot -e "set print '-'; stats '$stem.path' using \"lambda\" nooutput; print STATS_records, STATS_max; \
stats '$stem.path' using \"step\" nooutput; print STATS_min, STATS_max; \
set datafile separator comma; stats '$stem.path.csv' using \"lambda\" nooutput; print STATS_records, STATS_max")
echo "gnuplot: $gnuplot_out"
key=$(gnuplot -e "set terminal dumb 100 30; set key autotitle columnheader; plot '$stem.path' using \"w_over_rise\":\"lambda\" with lines, '' using 4:2 with lines")
echo "$key" | grep -q 'lambda' || fail "gnuplot's columnheader did not title the curve 'lambda': $key"

"$python" - "$stem" "$rows" "$gnuplot_out" <<'PYTHON'
import csv, sys
import numpy as np
import pandas as pd

stem, rows, gnuplot_out = sys.argv[1], int(sys.argv[2]), sys.argv[3].split()
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)


counts = {'step', 'n_contact', 'contact_regions', 'lcp_pivots', 'iterations', 'neg_pivots', 'node',
          'candidate', 'rigid'}
# the one-liners of README.md
a = np.genfromtxt(f'{stem}.path', names=True, dtype=None, encoding=None)
df = pd.read_csv(f'{stem}.path', sep=r'\s+', comment='#')
header = open(f'{stem}.path').readline().split()
check(list(a.dtype.names) == header, f'numpy names {a.dtype.names} != header {header}')
check(list(df.columns) == header, f'pandas columns {list(df.columns)} != header {header}')
check(len(a) == rows and len(df) == rows, f'{len(a)} numpy rows, {len(df)} pandas rows; the file has {rows}')
for name in header:
    integer = name in counts
    check(np.issubdtype(a.dtype[name], np.integer) == integer, f'numpy {name}: dtype {a.dtype[name]}')
    check(pd.api.types.is_integer_dtype(df[name]) == integer, f'pandas {name}: dtype {df[name].dtype}')
    check(np.array_equal(a[name], df[name].to_numpy()), f'{name}: numpy and pandas differ')
check(list(df['step']) == list(range(rows)), f'pandas step column {list(df["step"])[:5]}... is not 0, 1, ...')
check(df['lambda'].max() > 50.0, f'pandas lambda max {df["lambda"].max()} (ex. 2 passes K_lim ~ 83)')
check(int(gnuplot_out[0]) == rows and abs(float(gnuplot_out[1]) - df['lambda'].max()) <= 1e-9 * df['lambda'].max(),
      f'gnuplot lambda: {gnuplot_out[:2]} vs {rows} rows, max {df["lambda"].max()!r}')
check(float(gnuplot_out[2]) == 0 and float(gnuplot_out[3]) == df['step'].max(), f'gnuplot step: {gnuplot_out[2:4]}')
check(int(gnuplot_out[4]) == rows, f'gnuplot on the CSV: {gnuplot_out[4]} rows')
# the other tables
crit = pd.read_csv(f'{stem}.crit', sep=r'\s+', comment='#')
check(list(crit.columns[:3]) == ['kind', 'step', 'lambda'] and 'limit_max' in set(crit['kind']),
      f'pandas crit: {crit}')
c = np.genfromtxt(f'{stem}.crit', names=True, dtype=None, encoding=None)
check('limit_max' in set(c['kind']), f'numpy crit kinds {c["kind"]}')
shape = pd.read_csv(f'{stem}.shape', sep=r'\s+', comment='#')
s = np.genfromtxt(f'{stem}.shape', names=True, dtype=None, encoding=None)
check(len(shape) == len(s) and len(shape) % 11 == 0 and shape['node'].nunique() == 11,
      f'shape: {len(shape)} pandas rows, {len(s)} numpy rows, nodes {shape["node"].nunique()} (n = 10: 11 nodes)')
for name in ('step', 'node'):
    check(pd.api.types.is_integer_dtype(shape[name]) and np.issubdtype(s.dtype[name], np.integer),
          f'shape {name} not integer')
surface = pd.read_csv(f'{stem}.surface', sep=r'\s+', comment='#')
check(list(surface.columns) == ['medium', 'candidate', 'node', 'x', 'y', 'rigid'] and
      set(surface['rigid']) == {0} and len(surface) == 11, f'surface: {surface}')
# the CSV twins: the same tables for pandas' defaults and for the csv module
for ext, table in (('path', df), ('crit', crit), ('shape', shape), ('surface', surface)):
    twin = pd.read_csv(f'{stem}.{ext}.csv', comment='#')
    check(twin.equals(table), f'{ext}.csv differs from {ext} for pandas')
with open(f'{stem}.path.csv', newline='') as handle:
    records = [r for r in csv.reader(handle) if r and not r[0].startswith('#')]
check(records[0] == header and len(records) == rows + 1, f'csv module: {records[:2]}')
for failure in failures:
    print('FAIL:', failure)
print(f'numpy, pandas, gnuplot and csv read {rows} rows of {len(header)} named columns' if not failures else '')
sys.exit(1 if failures else 0)
PYTHON
echo ok
