#!/usr/bin/env bash
# Equilibrium paths as a PNG: the load parameter lambda (y) against any column (x) of one or several
# uniarc path files, with the limit points and bifurcations of the STEM.crit beside each path file.
#
#   scripts/plot_path.sh [-x COLUMN] [-y COLUMN] [-o OUT.png] [-t TITLE] [-C] [-l LABEL]... FILE.path...
#
#   -x COLUMN   x axis: a column name of the path header (default: the first tracked column, the one
#               after lambda) or a column number (1 = step)
#   -y COLUMN   y axis (default: lambda)
#   -o OUT.png  the picture (default: the first file with .png for .path)
#   -t TITLE    the title (default: the deck stem, or "equilibrium paths" for several decks)
#   -C          also mark the contact events (contact_start, contact_lost)
#   -l LABEL    legend of the next file, in the order of the files (repeatable; the rest as below)
#
# Legend: for a run of scripts/sweep.sh (FOLDER/sweep_<stem>_<name>/<value>/STEM.path) "name = value",
# otherwise the file's stem (with its folder when two files share a stem). Events are placed at the
# fractional step STEM.crit gives: its own value where the x column is tracked there, else the path
# column interpolated linearly between the two steps around the event.
set -euo pipefail

usage() { sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'; }
fail() { echo "plot_path.sh: $*" >&2; exit 2; }

xcolumn="" ycolumn=lambda out="" title="" contact=no
files=() labels=()
while [ $# -gt 0 ]; do
  case $1 in
    -x) [ $# -ge 2 ] || fail "-x needs a value"; xcolumn=$2; shift 2 ;;
    -y) [ $# -ge 2 ] || fail "-y needs a value"; ycolumn=$2; shift 2 ;;
    -o) [ $# -ge 2 ] || fail "-o needs a value"; out=$2; shift 2 ;;
    -t) [ $# -ge 2 ] || fail "-t needs a value"; title=$2; shift 2 ;;
    -C) contact=yes; shift ;;
    -l) [ $# -ge 2 ] || fail "-l needs a value"; labels+=("$2"); shift 2 ;;
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
script=$(LABELS="$label_list" python3 - "$xcolumn" "$ycolumn" "$out" "$title" "$contact" "$@" <<'PYTHON'
import os, sys

xcolumn, ycolumn, out, title, contact = sys.argv[1:6]
files = sys.argv[6:]
colours = ['#1f4e9c', '#b22222', '#228b22', '#ff8c00', '#6a3d9a', '#008b8b', '#8b4513', '#c71585',
           '#555555', '#9acd32']


def die(message):
    print(f'plot_path.sh: {message}', file=sys.stderr)
    sys.exit(2)


def header(path):
    with open(path) as handle:
        first = handle.readline()
    if not first.startswith('#'):
        die(f'{path}: no header line (not a uniarc table)')
    return first[1:].split()


def rows(path, count):
    result = []
    for line in open(path).read().splitlines()[1:]:
        fields = line.split()
        if len(fields) == count:
            result.append([float(x) for x in fields])
    return result


def resolve(names, column, path):
    """0-based index of a column given by name or 1-based number."""
    if column.isdigit():
        if not 1 <= int(column) <= len(names):
            die(f'{path}: no column {column} (it has {len(names)})')
        return int(column) - 1
    if column not in names:
        die(f'{path}: no column {column!r}; columns: {" ".join(names)}')
    return names.index(column)


def legend(path, stems):
    folder = os.path.dirname(os.path.abspath(path))
    sweep = os.path.dirname(folder)
    conf = os.path.join(sweep, 'sweep.conf')
    if os.path.isfile(conf):
        settings = dict(line.rstrip('\n').split('=', 1) for line in open(conf) if '=' in line)
        return f'{settings.get("name", "value")} = {os.path.basename(folder)}'
    stem = os.path.splitext(os.path.basename(path))[0]
    if stems.count(stem) > 1:
        return os.path.join(os.path.basename(folder), stem)
    return stem


def quote(text):
    return '"' + text.replace('\\', '\\\\').replace('"', '\\"') + '"'


labels = [l for l in os.environ.get('LABELS', '').split('\n') if l]
stems = [os.path.splitext(os.path.basename(f))[0] for f in files]
first_names = header(files[0])
if not xcolumn:
    xcolumn = first_names[2] if len(first_names) > 2 and first_names[2] != 'n_contact' else 'step'
kinds = {'limit_max': 'limit point', 'limit_min': 'limit point', 'bifurcation': 'bifurcation',
         'unilateral_bifurcation': 'lift-off bifurcation'}
if contact == 'yes':
    kinds.update({'contact_start': 'contact starts', 'contact_lost': 'contact lost'})
styles = {'limit point': 'pt 7 ps 1.6', 'bifurcation': 'pt 13 ps 1.9', 'lift-off bifurcation': 'pt 12 ps 1.9',
          'contact starts': 'pt 8 ps 1.5', 'contact lost': 'pt 10 ps 1.5'}
plots, blocks, used = [], [], []
for number, path in enumerate(files):
    names = header(path)
    ix, iy = resolve(names, xcolumn, path), resolve(names, ycolumn, path)
    colour = colours[number % len(colours)]
    plots.append(f'{quote(os.path.abspath(path))} using {ix + 1}:{iy + 1} with lines lw 2 '
                 f'lc rgb "{colour}" title {quote(labels[number] if number < len(labels) else legend(path, stems))} noenhanced')
    crit = os.path.splitext(path)[0] + '.crit'
    if not os.path.isfile(crit):
        continue
    crit_names = header(crit)[1:]
    path_rows = rows(path, len(names))
    points = {}
    for line in open(crit).read().splitlines()[1:]:
        fields = line.split()
        if len(fields) != len(crit_names) + 1 or fields[0] not in kinds:
            continue
        numbers = dict(zip(crit_names, (float(x) for x in fields[1:])))
        step = numbers['step']

        def value(column_index):
            name = names[column_index]
            if name in numbers:
                return numbers[name]
            for a, b in zip(path_rows, path_rows[1:]):
                if a[0] <= step <= b[0]:
                    t = (step - a[0]) / (b[0] - a[0]) if b[0] > a[0] else 0.0
                    return a[column_index] + t * (b[column_index] - a[column_index])
            return None
        x, y = value(ix), value(iy)
        if x is not None and y is not None:
            points.setdefault(kinds[fields[0]], []).append((x, y))
    for kind, found in points.items():
        block = f'$events{number}_{len(blocks)}'
        blocks.append(block + ' << EOD\n' + '\n'.join(f'{x!r} {y!r}' for x, y in found) + '\nEOD')
        plots.append(f'{block} using 1:2 with points {styles[kind]} lc rgb "{colour}" notitle')
        if kind not in used:
            used.append(kind)
for kind in used:
    plots.append(f'NaN with points {styles[kind]} lc rgb "black" title "{kind}"')

label = {'lambda': 'load parameter {/Symbol l}', 'step': 'step'}
if not title:
    title = stems[0] if len(set(stems)) == 1 else 'equilibrium paths'
print('set terminal pngcairo size 1000,700 enhanced font "Sans,11"')
print(f'set output {quote(out)}')
print(f'set title {quote(title)} noenhanced')
xname, yname = first_names[resolve(first_names, xcolumn, files[0])], first_names[resolve(first_names, ycolumn, files[0])]
print(f'set xlabel {quote(label.get(xname, xname))}' + ('' if xname in label else ' noenhanced'))
print(f'set ylabel {quote(label.get(yname, yname))}' + ('' if yname in label else ' noenhanced'))
print('set grid')
print('set key outside right top box')
print('set xzeroaxis lt -1 lw 0.5')
for block in blocks:
    print(block)
print('plot ' + ', \\\n     '.join(plots))
PYTHON
)
printf '%s\n' "$script" | gnuplot
echo "$out"
