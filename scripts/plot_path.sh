#!/usr/bin/env bash
# Equilibrium paths as a PNG: the load parameter lambda (y) against any column (x) of one or several
# uniarc path files, stable branches solid and unstable ones dashed, with the limit points and
# bifurcations of the STEM.crit beside each path file marked and labelled with their lambda.
#
#   scripts/plot_path.sh [-x COLUMN] [-y COLUMN] [-o OUT.png] [-t TITLE] [-C] [-l LABEL]... [-g FILE.gp]
#                        FILE.path...
#
#   -x COLUMN   x axis: a column name of the path header (default: the first tracked column, the one
#               after lambda) or a column number (1 = step)
#   -y COLUMN   y axis (default: lambda)
#   -o OUT.png  the picture (default: the first file with .png for .path)
#   -t TITLE    the title (default: the deck stem and the -D values all files share)
#   -C          also mark the contact events (contact_start, contact_lost)
#   -l LABEL    legend of the next file, in the order of the files (repeatable; the rest as below)
#   -g FILE.gp  also write the gnuplot commands (data included) to FILE.gp, to restyle the picture:
#               edit it and run `gnuplot FILE.gp`
#
# Legend: the -D values of each run (from the `# defines:` line of its path file) that differ between
# the files, as "k = 1e4"; a run without one of them gets no such part (its deck's value is not known
# here), but the deck stem; the deck stem too when the files come from different decks; the stem
# alone when nothing differs. A path that lies on another file's curve all along (within 1e-3 of the
# plot's extent) is drawn last, thin and with open circles, so that both stay visible. When the x or
# y column is a contact-region coordinate (s_contact_N), the rows without contact (n_contact = 0,
# where uniarc writes s = 0) are left out and the curve is broken there. A branch is unstable where the path's neg_pivots > 0 (the tangent stiffness
# with the contacts has a negative pivot); a branch changes style at the critical point between the
# two steps, or half-way when the file has none there. Events are placed at the fractional step
# STEM.crit gives: its own value where the x column is tracked there, else the path column
# interpolated linearly between the two steps around the event.
set -euo pipefail

usage() { sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'; }
fail() { echo "plot_path.sh: $*" >&2; exit 2; }

xcolumn="" ycolumn=lambda out="" title="" contact=no
files=() labels=() gp_file=""
while [ $# -gt 0 ]; do
  case $1 in
    -x) [ $# -ge 2 ] || fail "-x needs a value"; xcolumn=$2; shift 2 ;;
    -y) [ $# -ge 2 ] || fail "-y needs a value"; ycolumn=$2; shift 2 ;;
    -o) [ $# -ge 2 ] || fail "-o needs a value"; out=$2; shift 2 ;;
    -t) [ $# -ge 2 ] || fail "-t needs a value"; title=$2; shift 2 ;;
    -C) contact=yes; shift ;;
    -l) [ $# -ge 2 ] || fail "-l needs a value"; labels+=("$2"); shift 2 ;;
    -g) [ $# -ge 2 ] || fail "-g needs a file name"; gp_file=$2; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    --) shift; files+=("$@"); break ;;
    -?*) fail "unknown option $1 (see -h)" ;;
    *) files+=("$1"); shift ;;
  esac
done
set -- "${files[@]}"
[ $# -ge 1 ] || { usage >&2; exit 2; }
for file in "$@"; do [ -f "$file" ] || fail "$file: no such file"; done
command -v gnuplot >/dev/null 2>&1 || fail "gnuplot not found (scripts/install_deps.sh installs it)"
[ -n "$out" ] || out=${1%.path}.png

label_list=$(printf '%s\n' "${labels[@]}")
script=$(LABELS="$label_list" PYTHONPATH="$(dirname "${BASH_SOURCE[0]}")" python3 - "$xcolumn" "$ycolumn" "$out" "$title" "$contact" "$@" <<'PYTHON'
import os, sys
from uniarc_table import Table

xcolumn, ycolumn, out, title, contact = sys.argv[1:6]
files = sys.argv[6:]
colours = ['#1f4e9c', '#b22222', '#228b22', '#ff8c00', '#6a3d9a', '#008b8b', '#8b4513', '#c71585',
           '#555555', '#9acd32']


def die(message):
    print(f'plot_path.sh: {message}', file=sys.stderr)
    sys.exit(2)


def read(path):
    try:
        return Table(path)
    except ValueError as error:
        die(error)


def resolve(names, column, path):
    """0-based index of a column given by name or 1-based number."""
    if column.isdigit():
        if not 1 <= int(column) <= len(names):
            die(f'{path}: no column {column} (it has {len(names)})')
        return int(column) - 1
    if column not in names:
        die(f'{path}: no column {column!r}; columns: {" ".join(names)}')
    return names.index(column)


def quote(text):
    return '"' + text.replace('\\', '\\\\').replace('"', '\\"') + '"'


tables = [read(f) for f in files]
labels = [l for l in os.environ.get('LABELS', '').split('\n') if l]
stems = [t.stem for t in tables]
# legends from the -D values that differ between the files (a file without one: "deck's")
names_defined = []
for t in tables:
    names_defined += [n for n in t.defines if n not in names_defined]
varying = [n for n in names_defined if len({t.defines.get(n) for t in tables}) > 1]
shared = [n for n in names_defined if n not in varying]


def legend(number):
    if number < len(labels):
        return labels[number]
    t = tables[number]
    parts = [f'{n} = {t.defines[n]}' for n in varying if n in t.defines]
    lacking = any(n not in t.defines for n in varying)   # its deck's value: not known here
    # a run of scripts/sweep.sh: what its --label says the value means (e.g. k = 0: rigid)
    sweep = os.path.dirname(os.path.dirname(os.path.abspath(t.path)))
    if os.path.isfile(os.path.join(sweep, 'labels.txt')) and os.path.isfile(os.path.join(sweep, 'sweep.conf')):
        conf = dict(l.rstrip('\n').split('=', 1) for l in open(os.path.join(sweep, 'sweep.conf')) if '=' in l)
        meaning = dict(l.rstrip('\n').split('=', 1) for l in open(os.path.join(sweep, 'labels.txt')) if '=' in l)
        value = t.defines.get(conf.get('name'))
        if value in meaning:
            parts = [p + f' ({meaning[value]})' if p.startswith(conf['name'] + ' = ') else p for p in parts]
    if len(set(stems)) > 1 or not parts or lacking:
        same_stem = [i for i, s in enumerate(stems) if s == t.stem]
        stem = t.stem
        if len(same_stem) > 1 and not parts:   # same deck, same -D: the folders tell them apart
            stem = os.path.join(os.path.basename(os.path.dirname(os.path.abspath(t.path))), stem)
        parts.insert(0, stem)
    return ', '.join(parts)


first_names = tables[0].names
if not xcolumn:
    xcolumn = first_names[2] if len(first_names) > 2 and first_names[2] != 'n_contact' else 'step'
kinds = {'limit_max': 'limit point', 'limit_min': 'limit point', 'bifurcation': 'bifurcation',
         'unilateral_bifurcation': 'lift-off bifurcation'}
critical = set(kinds)
if contact == 'yes':
    kinds.update({'contact_start': 'contact starts', 'contact_lost': 'contact lost'})
# the contact events open, larger and drawn after the critical points: at a limit point that is also
# a contact event both markers show (the open triangle around the dot)
styles = {'limit point': 'pt 7 ps 1.6', 'bifurcation': 'pt 13 ps 1.9', 'lift-off bifurcation': 'pt 12 ps 1.9',
          'contact starts': 'pt 8 ps 2.6', 'contact lost': 'pt 10 ps 2.6'}
order = ['limit point', 'bifurcation', 'lift-off bifurcation', 'contact starts', 'contact lost']


def drawn_rows(table, ix, iy):
    """The rows of a path drawn, each with whether the curve breaks before it: without the rows out of
    contact when x or y is a contact-region coordinate (s_contact_N is 0 there, not a position)."""
    names = table.names
    region = names[ix].startswith('s_contact_') or names[iy].startswith('s_contact_')
    icontact = table.column('n_contact') if region else None
    result, gap = [], False
    for row in ([float(x) for x in r] for r in table.rows):
        if icontact is not None and row[icontact] <= 0:
            gap = bool(result)
            continue
        result.append((row, gap))
        gap = False
    return result


def on_curve(points, curve, extent):
    """Whether every point lies within 1e-3 of the plot's extent (per axis) of the polyline curve."""
    if not points or len(curve) < 2:
        return False
    sx, sy = extent

    def distance(p, a, b):
        px, py, ax, ay, bx, by = p[0] / sx, p[1] / sy, a[0] / sx, a[1] / sy, b[0] / sx, b[1] / sy
        dx, dy = bx - ax, by - ay
        length = dx * dx + dy * dy
        t = 0.0 if length == 0.0 else max(0.0, min(1.0, ((px - ax) * dx + (py - ay) * dy) / length))
        return ((px - ax - t * dx) ** 2 + (py - ay - t * dy) ** 2) ** 0.5
    return all(min(distance(p, a, b) for a, b in zip(curve, curve[1:])) < 1e-3 for p in points)


# which file's curve lies on another file's all along: drawn last, thin, with open circles
curves = []
for path, table in zip(files, tables):
    ix, iy = resolve(table.names, xcolumn, path), resolve(table.names, ycolumn, path)
    curves.append([(row[ix], row[iy]) for row, _ in drawn_rows(table, ix, iy)])
every = [p for c in curves for p in c]
extent = ((max(p[0] for p in every) - min(p[0] for p in every)) or 1.0,
          (max(p[1] for p in every) - min(p[1] for p in every)) or 1.0) if every else (1.0, 1.0)
coincident = [any(other != number and on_curve(curve, curves[other], extent) and
                  not (other > number and on_curve(curves[other], curve, extent)) for other in range(len(curves)))
              for number, curve in enumerate(curves)]
last_plots, marker_kind = [], {}
plots, blocks, used, label_lines = [], [], [], []
wanted_labels, all_points = [], []   # (x, y, side, text, colour) of the critical points; every point drawn
headroom, footroom = 0.0, 0.0         # how far labels reach above and below the frame (graph fractions)
any_unstable = False
for number, (path, table) in enumerate(zip(files, tables)):
    names = table.names
    ix, iy = resolve(names, xcolumn, path), resolve(names, ycolumn, path)
    colour = colours[number % len(colours)]
    rows = [[float(x) for x in row] for row in table.rows]
    kept = drawn_rows(table, ix, iy)
    ineg, icontact = table.column('neg_pivots'), table.column('n_contact')
    # events of STEM.crit: (kind, fractional step, x, y)
    events = []
    crit = os.path.splitext(path)[0] + '.crit'
    if os.path.isfile(crit):
        crit_table = read(crit)
        crit_names = crit_table.names[1:]
        for fields in crit_table.rows:
            numbers = dict(zip(crit_names, (float(x) for x in fields[1:])))
            step = numbers['step']

            def value(column_index):
                name = names[column_index]
                if name in numbers:
                    return numbers[name]
                region = name.startswith('s_contact_') and icontact is not None
                for a, b in zip(rows, rows[1:]):
                    if a[0] <= step <= b[0]:
                        t = (step - a[0]) / (b[0] - a[0]) if b[0] > a[0] else 0.0
                        if region and (a[icontact] <= 0) != (b[icontact] <= 0):
                            t = 0.0 if b[icontact] <= 0 else 1.0   # the end in contact (s = 0 is no position)
                        elif region and a[icontact] <= 0:
                            return None
                        return a[column_index] + t * (b[column_index] - a[column_index])
                return None
            x, y = value(ix), value(iy)
            if x is not None and y is not None:
                events.append((fields[0], step, x, y))
    # the path in runs of one stability; a run ends at the critical point between the two steps
    # around a change of neg_pivots (half-way when STEM.crit has none there)
    stable_rows, unstable_rows = [], []
    previous = None
    for k, (row, gap) in enumerate(kept):
        if gap and previous is not None:   # rows out of contact left out: the curve breaks here
            (unstable_rows if previous[1] else stable_rows).append('')
            previous = None
        point = (row[ix], row[iy])
        unstable = ineg is not None and row[ineg] > 0
        if previous is not None and unstable != previous[1]:
            inside = [e for e in events if e[0] in critical and kept[k - 1][0][0] <= e[1] <= row[0]]
            cut = (inside[0][2], inside[0][3]) if inside else tuple((a + b) / 2 for a, b in zip(previous[0], point))
            (unstable_rows if previous[1] else stable_rows).append(f'{cut[0]!r} {cut[1]!r}')
            (unstable_rows if previous[1] else stable_rows).append('')
            (unstable_rows if unstable else stable_rows).append(f'{cut[0]!r} {cut[1]!r}')
        (unstable_rows if unstable else stable_rows).append(f'{point[0]!r} {point[1]!r}')
        previous = (point, unstable)
    title_text = quote(legend(number))
    for kind_of_branch, block_rows, dash in (('stable', stable_rows, 1), ('unstable', unstable_rows, 2)):
        if not block_rows:
            continue
        block = f'$path{number}_{kind_of_branch}'
        blocks.append(block + ' << EOD\n' + '\n'.join(block_rows) + '\nEOD')
        if coincident[number]:
            last_plots.append(f'{block} using 1:2 with linespoints lw 1 dt {dash} pt 6 ps 1.3 '
                              f'pi {max(1, len(kept) // 20)} lc rgb "{colour}" title {title_text} noenhanced')
        else:
            plots.append(f'{block} using 1:2 with lines lw 2 dt {dash} lc rgb "{colour}" '
                         f'title {title_text} noenhanced')
        title_text = '""'     # one legend entry per file
        any_unstable = any_unstable or kind_of_branch == 'unstable'
    points = {}
    for kind, step, x, y in events:
        if kind in kinds:
            points.setdefault(kinds[kind], []).append((x, y))
        if kind in critical:
            # the critical point's lambda beside its marker, in the colour of its path
            # above a maximum, below a minimum, staggered by file so that nearby paths' labels part
            wanted_labels.append((x, y, -1 if kind == 'limit_min' else 1, "{/Symbol l} = " + f"{y:.4g}", colour))
    all_points += [(row[ix], row[iy]) for row, _ in kept]
    for kind, found in sorted(points.items(), key=lambda item: order.index(item[0])):
        block = f'$events{number}_{len(blocks)}'
        blocks.append(block + ' << EOD\n' + '\n'.join(f'{x!r} {y!r}' for x, y in found) + '\nEOD')
        plots.append(f'{block} using 1:2 with points {styles[kind]} lc rgb "{colour}" notitle')
        marker_kind[plots[-1]] = kind
        if kind not in used:
            used.append(kind)
# Each label above its maximum (below a minimum), raised further, a line at a time, until it overlaps
# no label placed before: boxes in graph fractions, from the data's extent (with the offsets below)
# and the frame's size in characters (1000 x 700 canvas, key outside: about 85 x 38 characters).
if wanted_labels and all_points:
    xs, ys = [p[0] for p in all_points], [p[1] for p in all_points]
    span_x, span_y = (max(xs) - min(xs)) or 1.0, (max(ys) - min(ys)) or 1.0
    span_x_graph, span_y_graph = span_x * 1.08, span_y * 1.22
    char_x, char_y = 1.0 / 85.0, 1.0 / 38.0
    placed = []
    for x, y, side, text, colour in wanted_labels:
        gx = (x - min(xs)) / span_x_graph
        gy = (y - min(ys) + 0.08 * span_y) / span_y_graph
        half_width = 0.5 * (len(text) - 8) * char_x + char_x   # the {/Symbol l} markup is one glyph
        for step in range(1, 12):
            rise = side * 1.4 * step
            centre = gy + rise * char_y
            box = (gx - half_width, gx + half_width, centre - 0.6 * char_y, centre + 0.6 * char_y)
            if all(box[1] < b[0] or box[0] > b[1] or box[3] < b[2] or box[2] > b[3] for b in placed):
                break
        placed.append(box)
        headroom = max(headroom, box[3] - 0.97)
        footroom = max(footroom, 0.03 - box[2])
        label_lines.append(f'set label {quote(text)} at {x!r},{y!r} center offset 0,{rise:g} '
                           f'tc rgb "{colour}" boxed front')
# drawn in this order: the lines, the coincident lines, then the markers (critical points, contact events)
markers = sorted((p for p in plots if ' with points ' in p), key=lambda p: order.index(marker_kind[p]))
plots = [p for p in plots if ' with points ' not in p] + last_plots + markers
if any_unstable:
    plots.append('NaN with lines lw 2 dt 1 lc rgb "black" title "stable (no negative pivot)"')
    plots.append('NaN with lines lw 2 dt 2 lc rgb "black" title "unstable (negative pivots)"')
for kind in used:
    plots.append(f'NaN with points {styles[kind]} lc rgb "black" title "{kind}' +
                 (' ({/Symbol l} beside it)' if kind in ('limit point', 'bifurcation', 'lift-off bifurcation') else '') + '"')

label = {'lambda': 'load parameter {/Symbol l}', 'step': 'step'}
if not title:
    title = stems[0] if len(set(stems)) == 1 else 'equilibrium paths'
    common = [f'{n} = {tables[0].defines[n]}' for n in shared if all(n in t.defines for t in tables)]
    if common:
        title += ' (' + ', '.join(common) + ')'
print('set terminal pngcairo size 1000,700 enhanced font "Sans,11"')
print(f'set output {quote(out)}')
print(f'set title {quote(title)} noenhanced')
xname, yname = first_names[resolve(first_names, xcolumn, files[0])], first_names[resolve(first_names, ycolumn, files[0])]
print(f'set xlabel {quote(label.get(xname, xname))}' + ('' if xname in label else ' noenhanced'))
print(f'set ylabel {quote(label.get(yname, yname))}' + ('' if yname in label else ' noenhanced'))
print('set grid')
print('set key outside right top box')
print('set xzeroaxis lt -1 lw 0.5')
# room for the labels: the offsets are fractions of the data's extent, the label reach of the frame's
print(f'set offsets 0, graph 0.08, graph {0.14 + 1.22 * headroom:.3f}, graph {0.08 + 1.22 * footroom:.3f}')
print('set style textbox opaque noborder margins 1, 1')
print('\n'.join(label_lines))
for block in blocks:
    print(block)
print('plot ' + ', \\\n     '.join(plots))
PYTHON
)
printf '%s\n' "$script" | gnuplot
if [ -n "$gp_file" ]; then printf '%s\n' "$script" > "$gp_file"; fi
echo "$out"
