#!/usr/bin/env bash
# Deformed shapes of a uniarc STEM.shape file as a PNG: chosen snapshots with the undeformed structure,
# the foundations and obstacles (from STEM.surface beside the shape file), the nodes in contact
# (reaction > 0, above round-off) marked, displacements magnified by a scale factor, equal axes.
#
#   scripts/plot_shapes.sh [-s STEPS] [-f SCALE] [-o OUT.png] [-t TITLE] [-F] [-r RATIO] [-g FILE.gp]
#                          FILE.shape
#
#   -s STEPS   comma-separated step numbers of snapshots in the file, or `all` (default: up to six
#              snapshots spread over the path, the last one included)
#   -f SCALE   displacement scale factor: drawn at x0 + SCALE*ux, y0 + SCALE*uy (default 1)
#   -o OUT.png the picture (default: FILE without .shape, with _shapes.png: out/arch.shape gives
#              out/arch_shapes.png)
#   -t TITLE   the title (default: the deck stem)
#   -F         free aspect: the drawing fills the frame, and the title states how many times the
#              vertical scale is the horizontal (for very shallow structures)
#   -r RATIO   a node is in contact when its reaction exceeds RATIO times the largest reaction in
#              the file (default 1e-6; uniarc leaves round-off of order 1e-28 at free nodes)
#   -g FILE.gp  also write the gnuplot commands (data included) to FILE.gp, to restyle the picture:
#               edit it and run `gnuplot FILE.gp`
#
# Each medium of STEM.surface (a foundation, springs or an obstacle) is drawn as a broad band through
# the points where its candidates' gaps close (brown: rigid, sand: elastic), under the undeformed
# structure (dashed grey). The nodes in contact are marked with a different symbol per snapshot. Nodes
# are joined in the file's order; a jump of more than three times the median node spacing breaks the
# line (separate members).
set -euo pipefail

usage() { sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'; }
fail() { echo "plot_shapes.sh: $*" >&2; exit 2; }

steps="" scale=1 out="" title="" free=no ratio=1e-6
gp_file=""
files=()
while [ $# -gt 0 ]; do
  case $1 in
    -s) [ $# -ge 2 ] || fail "-s needs a value"; steps=$2; shift 2 ;;
    -f) [ $# -ge 2 ] || fail "-f needs a value"; scale=$2; shift 2 ;;
    -o) [ $# -ge 2 ] || fail "-o needs a value"; out=$2; shift 2 ;;
    -t) [ $# -ge 2 ] || fail "-t needs a value"; title=$2; shift 2 ;;
    -r) [ $# -ge 2 ] || fail "-r needs a value"; ratio=$2; shift 2 ;;
    -g) [ $# -ge 2 ] || fail "-g needs a file name"; gp_file=$2; shift 2 ;;
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

script=$(PYTHONPATH="$(dirname "${BASH_SOURCE[0]}")" python3 - "$file" "$steps" "$scale" "$out" "$title" "$free" "$ratio" <<'PYTHON'
import math, os, sys
from uniarc_table import Table

path, steps, scale, out, title, free, ratio = sys.argv[1:8]
colours = ['#1f4e9c', '#b22222', '#228b22', '#ff8c00', '#6a3d9a', '#008b8b', '#8b4513', '#c71585']
# contact markers: a symbol and size per snapshot, the earlier ones larger, so that none hides another
markers = ['pt 6 ps 2.0', 'pt 7 ps 1.1', 'pt 4 ps 1.7', 'pt 5 ps 0.9', 'pt 8 ps 1.8', 'pt 9 ps 1.0',
           'pt 12 ps 1.9', 'pt 13 ps 1.0']


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
try:
    table = Table(path)
except ValueError as error:
    die(error)
names = table.names
need = ['step', 'lambda', 'x0', 'y0', 'ux', 'uy', 'reaction']
missing = [n for n in need if n not in names]
if missing:
    die(f'{path}: no column(s) {" ".join(missing)}; not a uniarc shape file')
column = {n: names.index(n) for n in names}
snapshots = []  # (step, lambda, [rows]) in file order
for row in table.numbers():
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
blocks, plots = [], []
every_point = list(undeformed)
# the media: STEM.surface beside the shape file
surface_file = os.path.splitext(path)[0] + '.surface'
if os.path.isfile(surface_file):
    surface = Table(surface_file)
    media = {}
    for row in surface.rows:
        medium = media.setdefault(row[surface.column('medium')], [int(row[surface.column('rigid')]), []])
        medium[1].append((float(row[surface.column('x')]), float(row[surface.column('y')])))
    for number, (name, (rigid, points)) in enumerate(media.items()):
        blocks += [f'$medium{number} << EOD', *polyline(points), 'EOD']
        colour = '#8b5a2b' if rigid else '#e0c187'
        kind = 'rigid' if rigid else 'elastic'
        plots.append(f'$medium{number} using 1:2 with lines lw 9 lc rgb "{colour}" '
                     f'title "{name} ({kind}; where its gap closes)" noenhanced')
        every_point += points
blocks += ['$undeformed << EOD', *polyline(undeformed), 'EOD']
plots.append('$undeformed using 1:2 with lines dt 2 lw 1.5 lc rgb "#606060" title "undeformed"')
contact_legend = []
for number, (step, load, rows) in enumerate(chosen):
    colour = colours[number % len(colours)]
    shape = [(r[column['x0']] + scale * r[column['ux']], r[column['y0']] + scale * r[column['uy']])
             for r in rows]
    every_point += shape
    touching = [p for p, r in zip(shape, rows) if r[column['reaction']] > threshold]
    blocks += [f'$shape{number} << EOD', *polyline(shape), 'EOD']
    label = f'step {step:g}, {{/Symbol l}} = {load:.4g}' + (f', {len(touching)} node{"s" if len(touching) != 1 else ""} in contact' if touching else '')
    plots.append(f'$shape{number} using 1:2 with lines lw 2 lc rgb "{colour}" title "{label}"')
    if touching:
        marker = markers[number % len(markers)]
        blocks += [f'$contact{number} << EOD', *(f'{x!r} {y!r}' for x, y in touching), 'EOD']
        plots.append(f'$contact{number} using 1:2 with points {marker} lc rgb "{colour}" notitle')
        contact_legend.append(marker)
if contact_legend:
    plots.append(f'NaN with points {contact_legend[0]} lc rgb "black" '
                 f'title "node in contact (a symbol per snapshot)"')
# The frame: a fixed plot area (screen fractions of the canvas below), so that the scales of x and y
# are known: equal, or (with -F) filling the area, with their ratio stated in the title.
# The key left-aligned a little right of the frame (its box never overlaps the frame), on a canvas
# wide enough for it: gnuplot sizes the box at about 10 px per character of its longest entry (the
# sample included), plus a margin.
longest = max(len(p.split(' title "')[-1].replace(' noenhanced', '').replace('{/Symbol l}', 'l')) for p in plots if ' title "' in p)
left_px, right_px, key_gap_px = 92, 736, 14
width_px, height_px = max(1150, right_px + key_gap_px + 10 * longest + 30), 760
left, right, bottom, top = left_px / width_px, right_px / width_px, 0.09, 0.90
area_w, area_h = (right - left) * width_px, (top - bottom) * height_px
xs = [p[0] for p in every_point]
ys = [p[1] for p in every_point]
x_low, x_high, y_low, y_high = min(xs), max(xs), min(ys), max(ys)
span_x = max(x_high - x_low, 1e-12 * max(abs(x_high), 1.0))
span_y = max(y_high - y_low, 1e-12 * max(abs(y_high), 1.0))
margin = 0.05
if free == 'yes':
    x_range = (x_low - margin * span_x, x_high + margin * span_x)
    y_range = (y_low - margin * span_y, y_high + margin * span_y)
    exaggeration = ((x_range[1] - x_range[0]) / area_w) / ((y_range[1] - y_range[0]) / area_h)
    scale_text = f'vertical scale {exaggeration:.3g} x the horizontal'
else:
    per_px = (1 + 2 * margin) * max(span_x / area_w, span_y / area_h)
    cx, cy = (x_low + x_high) / 2, (y_low + y_high) / 2
    x_range = (cx - per_px * area_w / 2, cx + per_px * area_w / 2)
    y_range = (cy - per_px * area_h / 2, cy + per_px * area_h / 2)
    scale_text = 'equal scales'
stem = os.path.splitext(os.path.basename(path))[0]
print(f'set terminal pngcairo size {width_px},{height_px} enhanced font "Sans,11"')
print(f'set output "{out}"')
print(f'set title "{(title or stem)}: deformed shapes, displacements x {scale:g}, {scale_text}" noenhanced')
print(f'set lmargin at screen {left}; set rmargin at screen {right}')
print(f'set bmargin at screen {bottom}; set tmargin at screen {top}')
print(f'set xrange [{x_range[0]!r}:{x_range[1]!r}]')
print(f'set yrange [{y_range[0]!r}:{y_range[1]!r}]')
print('set xlabel "x"')
print('set ylabel "y"')
print('set grid')
print(f'set key at screen {(right_px + key_gap_px) / width_px!r}, screen {top} left top Left reverse box '
      'spacing 1.15 samplen 2.5')
print('\n'.join(blocks))
print('plot ' + ', \\\n     '.join(plots))
PYTHON
)
printf '%s\n' "$script" | gnuplot
if [ -n "$gp_file" ]; then printf '%s\n' "$script" > "$gp_file"; fi
echo "$out"
