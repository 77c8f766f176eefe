#!/usr/bin/env bash
# Test of scripts/plot_path.sh and scripts/plot_shapes.sh: each must write a PNG (checked by its
# signature and a size that only a drawn picture reaches) from uniarc's files, and refuse a column
# that the path file does not have (exit 2). Their gnuplot commands (-g) must draw the unstable
# branches dashed and the stable ones solid, label each critical point with its lambda, take the
# legends from the -D values, draw the cavity of STEM.surface, and state the scale honestly (equal,
# or the vertical exaggeration that the frame really has). Skipped (77) without gnuplot.
#   test_plots.sh UNIARC WORKDIR
set -euo pipefail
uniarc=$1 work=$2
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
command -v gnuplot >/dev/null 2>&1 || { echo "gnuplot not installed: skipped"; exit 77; }
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*"; exit 1; }
png_ok() {
  [ -f "$1" ] || fail "$1 not written"
  [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "$1 is not a PNG"
  # an empty 1000x700 canvas with axes only compresses to a few kB; curves and legend add more
  [ "$(wc -c < "$1")" -gt 10000 ] || fail "$1 is only $(wc -c < "$1") bytes"
  echo "ok: $1 ($(wc -c < "$1") bytes)"
}
"$uniarc" "$source_dir/input/ring_rigid_cavity.inp" -o ring -D n=20 -q
"$uniarc" "$source_dir/input/ring_rigid_cavity.inp" -o springs -D n=20 -D k=1e4 -q
bash "$source_dir/scripts/plot_path.sh" -o paths.png -g paths.gp ring/ring_rigid_cavity.path springs/ring_rigid_cavity.path
png_ok paths.png
python3 - paths.gp ring/ring_rigid_cavity springs/ring_rigid_cavity <<'PYTHON'
import sys
script = open(sys.argv[1]).read()
failures = []
# both runs pass a limit point onto an unstable branch: each has a solid and a dashed block
for number in (0, 1):
    for branch, dash in (('stable', 1), ('unstable', 2)):
        if f'$path{number}_{branch} using 1:2 with lines lw 2 dt {dash}' not in script:
            failures.append(f'no {branch} branch (dt {dash}) of file {number + 1}')
# a label with lambda per limit point or bifurcation of the two .crit files
critical = 0
for stem in sys.argv[2:]:
    lines = open(stem + '.crit').read().splitlines()[1:]
    critical += sum(1 for l in lines if l.split() and l.split()[0] in ('limit_max', 'limit_min', 'bifurcation'))
labels = script.count('set label "{/Symbol l} = ')
if critical == 0 or labels != critical:
    failures.append(f'{labels} lambda labels for {critical} critical points')
# legends from -D: only the second run has -D k=1e4 (both have n=20, which goes to the title); the
# first gets its deck stem (in its folder: the two stems are the same), no "k = ..." of its own
if 'title "k = 1e4"' not in script or 'title "ring/ring_rigid_cavity"' not in script or 'title "k as' in script:
    failures.append('legends are not "ring/ring_rigid_cavity" (deck stem in its folder) and "k = 1e4"')
if 'set title "ring_rigid_cavity (n = 20)"' not in script:
    failures.append('the title does not show the shared -D n=20')
for failure in failures:
    print('FAIL:', failure)
sys.exit(1 if failures else 0)
PYTHON
bash "$source_dir/scripts/plot_path.sh" -x s_contact_1 -C -g phi.gp ring/ring_rigid_cavity.path
png_ok ring/ring_rigid_cavity.png
# the same path twice (another folder): the second lies on the first all along and must stay visible
mkdir -p again && cp ring/ring_rigid_cavity.path ring/ring_rigid_cavity.crit again/
bash "$source_dir/scripts/plot_path.sh" -o same.png -g same.gp ring/ring_rigid_cavity.path again/ring_rigid_cavity.path
png_ok same.png
PYTHONPATH="$source_dir/scripts" python3 - phi.gp same.gp ring/ring_rigid_cavity.path <<'PYTHON'
import re, sys
from uniarc_table import Table
failures = []
phi, same = (open(name).read() for name in sys.argv[1:3])
# -x s_contact_1: the rows without contact (s = 0 there) are left out, not joined along s = 0
table = Table(sys.argv[3])
icontact, ix = table.column('n_contact'), table.column('s_contact_1')
if not any(float(r[icontact]) == 0 for r in table.rows):
    failures.append('the test path has no row without contact: nothing is tested')
drawn = [float(line.split()[0]) for block in re.findall(r'\$path0_\w+ << EOD\n(.*?)\nEOD', phi, re.S)
         for line in block.splitlines() if line.strip()]
contact_s = {float(r[ix]) for r in table.rows if float(r[icontact]) > 0}
if not drawn or any(x == 0.0 and 0.0 not in contact_s for x in drawn):
    failures.append('rows without contact (s_contact_1 = 0) are drawn')
# -C: the contact events drawn after the critical points, larger, so that neither hides the other
markers = re.findall(r'^\s*(?:plot )?\$events\S+ using 1:2 with points pt (\d+) ps ([\d.]+)', phi, re.M)
critical = [(i, float(ps)) for i, (pt, ps) in enumerate(markers) if pt in ('7', '12', '13')]
events = [(i, float(ps)) for i, (pt, ps) in enumerate(markers) if pt in ('8', '10')]
if not critical or not events:
    failures.append(f'expected critical points and contact events among the markers: {markers}')
elif max(i for i, _ in critical) > min(i for i, _ in events) or max(p for _, p in critical) >= min(p for _, p in events):
    failures.append(f'contact events not drawn after and larger than the critical points: {markers}')
# coincident curves: the second drawn after the first, thin, with open circles
plot = same[same.index('plot '):]
first = plot.find('$path0_stable using 1:2 with lines lw 2')
second = plot.find('$path1_stable using 1:2 with linespoints lw 1')
if first < 0 or second < first:
    failures.append('the coincident second path is not drawn after the first with points')
for failure in failures:
    print('FAIL:', failure)
sys.exit(1 if failures else 0)
PYTHON
bash "$source_dir/scripts/plot_shapes.sh" -f 5 -s 10,40 -o shapes.png -g shapes.gp ring/ring_rigid_cavity.shape
png_ok shapes.png
# a shallow arch with -F: the title's vertical exaggeration must be the frame's
"$uniarc" "$source_dir/input/arch_foundation_below.inp" -o arch -D n=10 -D k=1e4 -q
bash "$source_dir/scripts/plot_shapes.sh" -F -g arch.gp arch/arch_foundation_below.shape
png_ok arch/arch_foundation_below_shapes.png
python3 - shapes.gp arch.gp <<'PYTHON'
import re, sys
failures = []


def frame(script):
    """Data units per pixel in x and y of the plot area the script fixes."""
    size = [float(x) for x in re.search(r'size (\d+),(\d+)', script).groups()]
    margin = {k: float(v) for k, v in re.findall(r'set (\w)margin at screen ([\d.]+)', script)}
    x = [float(v) for v in re.search(r'set xrange \[([^:]+):([^\]]+)\]', script).groups()]
    y = [float(v) for v in re.search(r'set yrange \[([^:]+):([^\]]+)\]', script).groups()]
    return ((x[1] - x[0]) / ((margin['r'] - margin['l']) * size[0]),
            (y[1] - y[0]) / ((margin['t'] - margin['b']) * size[1]))


ring, arch = (open(name).read() for name in sys.argv[1:3])
per_x, per_y = frame(ring)
if 'equal scales' not in ring or abs(per_x / per_y - 1) > 1e-9:
    failures.append(f'ring: x and y units per pixel {per_x!r}, {per_y!r} are not equal, or the title does not say so')
if '$medium0 using 1:2 with lines' not in ring or 'title "cavity (rigid' not in ring:
    failures.append('the rigid cavity of STEM.surface is not drawn')
per_x, per_y = frame(arch)
stated = re.search(r'vertical scale ([\d.]+) x the horizontal', arch)
if not stated or abs(float(stated.group(1)) / (per_x / per_y) - 1) > 5e-3:   # 3 significant digits
    failures.append(f'arch: title says {stated and stated.group(0)!r}, the frame has {per_x / per_y!r}')
if 'title "bed (elastic' not in arch:
    failures.append('the elastic bed of STEM.surface is not drawn')
# the legend box to the right of the frame, never over it
for name, script in (('ring', ring), ('arch', arch)):
    key = re.search(r'set key at screen ([\d.]+), screen [\d.]+ left top', script)
    right = float(re.search(r'set rmargin at screen ([\d.]+)', script).group(1))
    if not key or float(key.group(1)) <= right + 0.005:
        failures.append(f'{name}: the key is not left-aligned right of the frame (rmargin {right})')
for failure in failures:
    print('FAIL:', failure)
sys.exit(1 if failures else 0)
PYTHON
code=0
bash "$source_dir/scripts/plot_path.sh" -x no_such_column -o never.png ring/ring_rigid_cavity.path || code=$?
[ "$code" = 2 ] && [ ! -e never.png ] || fail "unknown column: exit $code, expected 2 and no picture"
code=0
bash "$source_dir/scripts/plot_shapes.sh" -s 7 -o never.png ring/ring_rigid_cavity.shape || code=$?
[ "$code" = 2 ] && [ ! -e never.png ] || fail "missing snapshot: exit $code, expected 2 and no picture"
echo ok
