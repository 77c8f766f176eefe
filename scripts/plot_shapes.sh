#!/usr/bin/env bash
# Deformed shapes of a uniarc STEM.shape file as a PNG: chosen snapshots with the undeformed structure,
# the nodes in contact (reaction > 0, above round-off) highlighted, displacements magnified by a scale factor, equal axes.
#
#   scripts/plot_shapes.sh [-s STEPS] [-f SCALE] [-o OUT.png] [-t TITLE] [-F] [-r RATIO] FILE.shape
#
#   -s STEPS   comma-separated step numbers of snapshots in the file, or `all` (default: up to six
#              snapshots spread over the path, the last one included)
#   -f SCALE   displacement scale factor: drawn at x0 + SCALE*ux, y0 + SCALE*uy (default 1)
#   -o OUT.png the picture (default: FILE with .png for .shape)
#   -t TITLE   the title (default: the deck stem)
#   -F         free aspect ratio instead of equal axes (for very shallow structures)
#   -r RATIO   a node is in contact when its reaction exceeds RATIO times the largest reaction in
#              the file (default 1e-6; uniarc leaves round-off of order 1e-28 at free nodes)
#
# The undeformed structure is the first snapshot's x0, y0; for a structure fitted to a cavity or laid
# on a foundation without a gap (examples 1-3) it is also the obstacle's or foundation's line. Nodes
# are joined in the file's order; a jump of more than three times the median node spacing breaks the
# line (separate members).
set -euo pipefail

usage() { sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'; }
fail() { echo "plot_shapes.sh: $*" >&2; exit 2; }

steps="" scale=1 out="" title="" free=no ratio=1e-6
files=()
while [ $# -gt 0 ]; do
  case $1 in
    -s) [ $# -ge 2 ] || fail "-s needs a value"; steps=$2; shift 2 ;;
    -f) [ $# -ge 2 ] || fail "-f needs a value"; scale=$2; shift 2 ;;
    -o) [ $# -ge 2 ] || fail "-o needs a value"; out=$2; shift 2 ;;
    -t) [ $# -ge 2 ] || fail "-t needs a value"; title=$2; shift 2 ;;
    -r) [ $# -ge 2 ] || fail "-r needs a value"; ratio=$2; shift 2 ;;
    -F) free=yes; shift ;;
    -h|--help) usage; exit 0 ;;
    --) shift; files+=("$@"); break ;;
    -?*) fail "unknown option $1 (see -h)" ;;
    *) files+=("$1"); shift ;;
  esac
done
set -- "${files[@]}"
[ $# -eq 1 ] || { usage >&2; exit 2; }
file=$1
[ -f "$file" ] || fail "$file: no such file"
command -v gnuplot >/dev/null 2>&1 || fail "gnuplot not found (scripts/install_deps.sh installs it)"
[ -n "$out" ] || out=${file%.shape}_shapes.png

script=$(python3 - "$file" "$steps" "$scale" "$out" "$title" "$free" "$ratio" <<'PYTHON'
import math, os, sys

path, steps, scale, out, title, free, ratio = sys.argv[1:8]
colours = ['#1f4e9c', '#b22222', '#228b22', '#ff8c00', '#6a3d9a', '#008b8b', '#8b4513', '#c71585']


def die(message):
    print(f'plot_shapes.sh: {message}', file=sys.stderr)
    sys.exit(2)


try:
    scale = float(scale)
except ValueError:
    die(f'-f {scale}: not a number')
try:
    ratio = float(ratio)
except ValueError:
    die(f'-r {ratio}: not a number')
lines = open(path).read().split('\n')
if not lines or not lines[0].startswith('#'):
    die(f'{path}: no header line')
names = lines[0][1:].split()
need = ['step', 'lambda', 'x0', 'y0', 'ux', 'uy', 'reaction']
missing = [n for n in need if n not in names]
if missing:
    die(f'{path}: no column(s) {" ".join(missing)}; not a uniarc shape file')
column = {n: names.index(n) for n in names}
snapshots = []  # (step, lambda, [rows]) in file order
for line in lines[1:]:
    fields = line.split()
    if len(fields) != len(names):
        continue
    row = [float(x) for x in fields]
    if not snapshots or snapshots[-1][0] != row[column['step']]:
        snapshots.append((row[column['step']], row[column['lambda']], []))
    snapshots[-1][2].append(row)
if not snapshots:
    die(f'{path}: no snapshots')
available = [s for s, _, _ in snapshots]
if steps == 'all':
    chosen = snapshots
elif steps:
    chosen = []
    for item in steps.split(','):
        try:
            wanted = float(item)
        except ValueError:
            die(f'-s {steps}: {item!r} is not a step number')
        match = [s for s in snapshots if s[0] == wanted]
        if not match:
            die(f'no snapshot at step {item}; the file has steps {" ".join(f"{s:g}" for s in available)}')
        chosen.append(match[0])
else:
    later = [s for s in snapshots if s[0] > 0] or snapshots
    if len(later) <= 6:
        chosen = later
    else:
        chosen = [later[round(i * (len(later) - 1) / 5)] for i in range(6)]


def polyline(points):
    """Gnuplot rows with a blank line where consecutive nodes are far apart (separate members)."""
    gaps = [math.dist(a, b) for a, b in zip(points, points[1:])]
    limit = 3.0 * sorted(gaps)[len(gaps) // 2] if gaps else 0.0
    out_rows = []
    for i, point in enumerate(points):
        if i > 0 and gaps[i - 1] > limit > 0.0:
            out_rows.append('')
        out_rows.append(f'{point[0]!r} {point[1]!r}')
    return out_rows


# uniarc writes round-off (|r| ~ 1e-28) at some nodes out of contact: a node is in contact when its
# reaction exceeds a fraction of the largest reaction in the file
largest = max(r[column['reaction']] for _, _, rows in snapshots for r in rows)
threshold = max(largest, 0.0) * ratio
first = snapshots[0][2]
undeformed = [(r[column['x0']], r[column['y0']]) for r in first]
blocks = ['$undeformed << EOD', *polyline(undeformed), 'EOD']
plots = ['$undeformed using 1:2 with lines dt 2 lw 1.5 lc rgb "#808080" title "undeformed"']
contact_legend = False
for number, (step, load, rows) in enumerate(chosen):
    colour = colours[number % len(colours)]
    shape = [(r[column['x0']] + scale * r[column['ux']], r[column['y0']] + scale * r[column['uy']])
             for r in rows]
    touching = [p for p, r in zip(shape, rows) if r[column['reaction']] > threshold]
    blocks += [f'$shape{number} << EOD', *polyline(shape), 'EOD']
    label = f'step {step:g}, {{/Symbol l}} = {load:.4g}' + (f', {len(touching)} nodes in contact' if touching else '')
    plots.append(f'$shape{number} using 1:2 with lines lw 2 lc rgb "{colour}" title "{label}"')
    if touching:
        blocks += [f'$contact{number} << EOD', *(f'{x!r} {y!r}' for x, y in touching), 'EOD']
        plots.append(f'$contact{number} using 1:2 with points pt 7 ps 1.1 lc rgb "{colour}" notitle')
        contact_legend = True
if contact_legend:
    plots.append('NaN with points pt 7 ps 1.1 lc rgb "black" title "node in contact (reaction > 0)"')
xs = [p[0] for p in undeformed]
ys = [p[1] for p in undeformed]
stem = os.path.splitext(os.path.basename(path))[0]
print('set terminal pngcairo size 1000,750 enhanced font "Sans,11"')
print(f'set output "{out}"')
print(f'set title "{(title or stem)}: deformed shapes, displacements x {scale:g}" noenhanced')
print('set xlabel "x"')
print('set ylabel "y"')
print('set grid')
if free != 'yes':
    print('set size ratio -1')
print('set key outside below box')
print('set offsets graph 0.04, graph 0.04, graph 0.04, graph 0.04')
print('\n'.join(blocks))
print('plot ' + ', \\\n     '.join(plots))
PYTHON
)
printf '%s\n' "$script" | gnuplot
echo "$out"
