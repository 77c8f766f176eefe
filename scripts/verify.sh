#!/usr/bin/env bash
# Regenerate docs/verification.md (and its pictures in docs/img/) from uniarc's own runs.
#
#   scripts/verify.sh [--uniarc BIN] [--work DIR] [--output FILE]
#
#   --uniarc BIN   use this uniarc (default: build a Release uniarc in build-verify/)
#   --work DIR     where the runs go (default: build-verify/verify)
#   --output FILE  the report (default: docs/verification.md; pictures go to img/ beside it)
#
# Every check of the regression tests (tests/regression/CMakeLists.txt, read as the source of truth:
# decks, -D overrides, references and tolerances) is run again and listed with its reference, the
# reference's source, uniarc's value and the relative error; a mesh-convergence study of the main cases,
# the k sweep of ex. 1 (the paper's Fig. 6) and the plots are added. Nothing in the report is typed by
# hand except the prose and the literature references, which carry their sources. The tests of the
# foundations and soil springs (Pasternak bed, tangential springs, plastic springs and beds) that run
# through checker scripts of their own (pasternak_check.py, agree_check.py, plastic_check.py, ...) are
# run as CTest runs them, and their printed values are listed with their section.
# Exit status: 0 when every check passes, 1 when some fail (the report is written in both cases).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
uniarc="" work="$root/build-verify/verify" output="$root/docs/verification.md"
while [ $# -gt 0 ]; do
  case $1 in
    -h|--help) sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    --uniarc) uniarc=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --output) output=$2; shift 2 ;;
    *) echo "verify.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done
command -v gnuplot >/dev/null 2>&1 || { echo "verify.sh: gnuplot is needed (scripts/install_deps.sh)" >&2; exit 2; }
build_type=given
if [ -z "$uniarc" ]; then
  echo "verify.sh: building uniarc (Release) in build-verify/" >&2
  cmake -S "$root" -B "$root/build-verify" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$root/build-verify" -j"$(nproc)" --target uniarc >/dev/null
  uniarc="$root/build-verify/uniarc"
  build_type=Release
fi
[ -x "$uniarc" ] || { echo "verify.sh: $uniarc is not a program" >&2; exit 2; }
uniarc=$(cd "$(dirname "$uniarc")" && pwd)/$(basename "$uniarc")
mkdir -p "$work"
work=$(cd "$work" && pwd)
mkdir -p "$(dirname "$output")/img"
start=$(date +%s)
python3 - "$root" "$uniarc" "$work" "$output" "$build_type" "$start" <<'PYTHON'
import argparse, concurrent.futures, datetime, math, os, re, shlex, shutil, subprocess, sys, time

root, uniarc, work, output, build_type, start = sys.argv[1:7]
sys.path.insert(0, os.path.join(root, 'tests', 'regression'))
from uniarc_check import read_table, read_events, find_event, value_where, split_event  # noqa: E402

image_dir = os.path.join(os.path.dirname(output), 'img')


def source_revision():
    """The commit the report is made from, `-dirty` when a tracked file differs from it — other than
    this script's own outputs (the report and its pictures, which a run rewrites before the report is
    committed): read before anything is written."""
    head = subprocess.run(['git', '-C', root, 'rev-parse', '--short', 'HEAD'], capture_output=True, text=True)
    if head.returncode != 0:
        return ''
    outputs = [os.path.relpath(path, root) for path in (output, image_dir)]
    changed = subprocess.run(['git', '-C', root, 'status', '--porcelain', '--untracked-files=no', '--', '.'] +
                             [f':(exclude){path}' for path in outputs if not path.startswith('..')],
                             capture_output=True, text=True).stdout.strip()
    return head.stdout.strip() + ('-dirty' if changed else '')


revision = source_revision()
jobs = os.cpu_count() or 1


def log(text):
    print(f'verify.sh: {text}', file=sys.stderr, flush=True)


# --- the regression tests, as CMake declares them ----------------------------------------------------
def cmake_calls(text, command):
    """Argument lists of every `command(...)` call of a CMake file (comment lines dropped)."""
    lines = [line for line in text.splitlines() if not line.lstrip().startswith('#')]
    text = '\n'.join(lines)
    calls, position = [], 0
    while True:
        begin = text.find(command + '(', position)
        if begin < 0:
            return calls
        end, quoted = begin + len(command) + 1, False   # the closing parenthesis outside quotes
        while end < len(text) and (quoted or text[end] != ')'):
            quoted = quoted != (text[end] == '"')
            end += 1
        calls.append(shlex.split(text[begin + len(command) + 1:end]))
        position = end + 1


def substitute(word):
    return (word.replace('${DECKS}', os.path.join(root, 'tests', 'regression', 'decks'))
                .replace('${PROJECT_SOURCE_DIR}', root))


parser = argparse.ArgumentParser()
for option in ('--define', '--expect', '--expect-row-where', '--expect-max', '--expect-min',
               '--expect-snap-back', '--expect-crit', '--expect-crit-column', '--expect-crit-count',
               '--expect-crit-before', '--expect-crit-path', '--expect-all', '--expect-stderr'):
    parser.add_argument(option, action='append', default=[])
parser.add_argument('--where-exact', action='store_true')
parser.add_argument('--reference')
parser.add_argument('--rtol', type=float)
parser.add_argument('--atol', type=float)
parser.add_argument('--expect-exit', type=int, default=0)

def expand_foreach(text):
    """The CMake loops `foreach(var a b ...) BODY endforeach()` (not nested) written out: BODY once per
    value with ${var} replaced, so that every test of a loop is read like the others."""
    loop = re.compile(r'^foreach\((\w+)((?:\s+[^)\s]+)+)\)\n(.*?)^endforeach\(\)\n', re.S | re.M)
    pick = re.compile(r'^\s*list\(GET\s+(\w+)\s+(\d+)\s+(\w+)\)\n', re.M)
    swap = re.compile(r'^\s*string\(REPLACE\s+"([^"]*)"\s+"([^"]*)"\s+(\w+)\s+\$\{(\w+)\}\)\n', re.M)

    def body(template, variable, value):
        """One pass of a loop: `list(GET variable i name)` lines (a value "a;b" read as a list) and
        `string(REPLACE "x" "y" name ${variable})` lines set ${name}; then ${variable} and those names
        are replaced."""
        value = value.strip('"')
        names = {}
        for source, index, name in pick.findall(template):
            if source == variable:
                names[name] = value.split(';')[int(index)]
        for old, new, name, source in swap.findall(template):
            if source == variable:
                names[name] = value.replace(old, new)
        text = swap.sub('', pick.sub('', template)).replace('${' + variable + '}', value)
        for name, item in names.items():
            text = text.replace('${' + name + '}', item)
        return text

    return loop.sub(lambda m: ''.join(body(m.group(3), m.group(1), value)
                                      for value in shlex.split(m.group(2))), text)


cmake_text = expand_foreach(open(os.path.join(root, 'tests', 'regression', 'CMakeLists.txt')).read())
tests = []
for words in cmake_calls(cmake_text, 'uniarc_regression'):
    args, unknown = parser.parse_known_args([substitute(w) for w in words[2:]])
    tests.append({'name': words[0], 'deck': substitute(words[1]), 'args': args, 'unknown': unknown})
convergence_tests = []
for words in cmake_calls(cmake_text, 'add_test'):
    if '${UNIARC_CONVERGENCE}' not in words:
        continue
    rest = [substitute(w) for w in words[words.index('${UNIARC_CONVERGENCE}') + 1:]]
    conv = argparse.ArgumentParser()
    for option in ('--deck', '--parameter', '--column'):
        conv.add_argument(option)
    conv.add_argument('--meshes', type=int, nargs='+')
    for option in ('--exact', '--order', '--order-tolerance', '--rtol'):
        conv.add_argument(option, type=float)
    parsed, _ = conv.parse_known_args(rest)
    convergence_tests.append({'name': words[words.index('NAME') + 1], 'args': parsed})


# Tests run by a checker script of their own (pasternak_check.py, agree_check.py, plastic_check.py,
# ...): add_test calls and the wrappers uniarc_forces_test / uniarc_plastic_test, with the CMake
# variables of the file (set(NAME value)) substituted. They are run as CTest runs them, and pass when
# the script exits 0; their output (the values and references they print) goes into the report. Only
# those of the report's sections are collected (SCRIPT_PREFIXES, from SECTIONS below).
WRAPPERS = {'uniarc_forces_test': '${UNIARC_TABLES_PYTHON} ${UNIARC_FORCES_CHECK}',
            'uniarc_plastic_test': '${UNIARC_PLASTIC_PYTHON} ${UNIARC_PLASTIC_CHECK}'}
cmake_variables = {
    'CMAKE_CURRENT_SOURCE_DIR': os.path.join(root, 'tests', 'regression'),
    'PROJECT_SOURCE_DIR': root,
    'OUT': os.path.join(work, 'scripts'),
}


def script_python():
    """The first of python3 and /usr/bin/python3 that imports numpy, scipy and pandas (the checkers'
    modules, as the CMake file looks for them); python3 if none does (the tests then fail, visibly)."""
    for candidate in ('python3', '/usr/bin/python3'):
        found = shutil.which(candidate)
        if found and subprocess.run([found, '-c', 'import numpy, scipy.optimize, pandas'],
                                    capture_output=True).returncode == 0:
            return found
    return shutil.which('python3') or sys.executable


for name in ('Python3_EXECUTABLE', 'UNIARC_TABLES_PYTHON', 'UNIARC_PLASTIC_PYTHON', 'UNIARC_VTK_PYTHON'):
    cmake_variables[name] = script_python()
for words in cmake_calls(cmake_text, 'set'):
    if len(words) == 2 and words[0] not in cmake_variables and words[1].startswith('${CMAKE_CURRENT_SOURCE_DIR}'):
        cmake_variables[words[0]] = words[1].replace('${CMAKE_CURRENT_SOURCE_DIR}',
                                                     cmake_variables['CMAKE_CURRENT_SOURCE_DIR'])


def expand(word):
    word = substitute(word).replace('$<TARGET_FILE:uniarc>', uniarc)
    for name, value in cmake_variables.items():
        word = word.replace('${' + name + '}', value)
    return word


def collect_script_tests(prefixes):
    found = []
    for words in cmake_calls(cmake_text, 'add_test'):
        if 'COMMAND' not in words or '${UNIARC_CHECK}' in words or '${UNIARC_CONVERGENCE}' in words:
            continue
        name = words[words.index('NAME') + 1]
        if name.startswith(prefixes):
            found.append({'name': name, 'command': words[words.index('COMMAND') + 1:]})
    for wrapper, head in WRAPPERS.items():
        for words in cmake_calls(cmake_text, wrapper):
            if words[0].startswith(prefixes):
                found.append({'name': words[0], 'command': head.split() + [
                    '--uniarc', '$<TARGET_FILE:uniarc>', '--deck', words[1], '--out', '${OUT}/' + words[0]] + words[2:]})
    for test in found:
        test['command'] = [expand(word) for word in test['command']]
        test['unresolved'] = [w for w in test['command'] if '${' in w or '$<' in w]
        test['checker'] = next((os.path.basename(w) for w in test['command'] if w.endswith('.py')), '?')
        deck = test['command'][test['command'].index('--deck') + 1] if '--deck' in test['command'] else None
        test['deck'] = os.path.relpath(deck, root) if deck else None
    return found


# --- running uniarc ------------------------------------------------------------------------------------
def run(deck, out, defines):
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    command = [uniarc, deck, '-o', out, '-q']
    for definition in defines:
        command += ['-D', definition]
    done = subprocess.run(command, capture_output=True, text=True)
    stem = os.path.splitext(os.path.basename(deck))[0]
    return {'code': done.returncode, 'stderr': done.stderr.strip(), 'stem': stem,
            'path': os.path.join(out, stem + '.path'), 'crit': os.path.join(out, stem + '.crit'),
            'shape': os.path.join(out, stem + '.shape'), 'command': ' '.join(command[1:])}


def run_all(jobs_list):
    """Run (key, deck, out, defines) tuples on all cores; results by key."""
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = {key: pool.submit(run, deck, out, defines) for key, deck, out, defines in jobs_list}
        return {key: future.result() for key, future in futures.items()}


# --- where each reference comes from (the paper's section 6 and the literature cited with each value) ---------------
SOURCES = [
    # (test name prefix, check label substring or '', source)
    ('linear_cantilever_tip_load', '', 'closed form: u = FL/EA, w = PL³/3EI, θ = PL²/2EI'),
    ('linear_cantilever_tip_moment', '', 'closed form: w = ML²/2EI, θ = ML/EI'),
    ('linear_propped_beam', '', 'closed form: w = 7PL³/768EI, θ = PL²/32EI'),
    ('linear_portal_frame', '', 'closed form (virtual work, axial strain included)'),
    ('linear_quarter_ring_castigliano', '', 'Castigliano\'s closed form'),
    ('static_contact_prop', '', 'the LCP solved by hand (deck comment)'),
    ('static_contact_rigid_stop', '', 'the LCP solved by hand (deck comment)'),
    ('static_contact_bonded_winkler_hetenyi', '', 'Hetényi 1946, ch. V (free–free finite beam)'),
    ('static_contact_tensionless_bed', '', 'w₀ = coth(π/2) Pβ/(2k) (benchmarks.md (b))'),
    ('loads_thermal_bar', '', 'N = −EAαΔT (Timoshenko & Goodier 1970 §150)'),
    ('loads_thermal_gradient', '', 'κ = −αΔT_d/h (Boley & Weiner 1960 §9.9)'),
    ('loads_thermal_large_rotation', '', 'the polygon of stress-free chords (deck comment)'),
    ('loads_settlement_two_span', '', 'superposition (Timoshenko & Young 1965 §6.3): w(L/2) = −11δ/16'),
    ('loads_weight_bonded_winkler_hetenyi', '', 'w/k + Hetényi 1946, ch. V'),
    ('loads_ring_hydrostatic', '', 'Fourier series of the inextensible ring (deck comment)'),
    ('nonlinear_elastica', '', 'Mattiasson 1981, Table 1'),
    ('nonlinear_euler_pinned', '', 'Timoshenko & Gere 1961: π²EI/L²'),
    ('nonlinear_euler_clamped_free', '', 'Timoshenko & Gere 1961: π²EI/(4L²)'),
    ('nonlinear_euler_clamped_clamped', '', 'Timoshenko & Gere 1961: 4π²EI/L²'),
    ('nonlinear_walker_arch_full_bifurcation', 'bifurcation', 'regression value (the lead\'s run; no literature value)'),
    ('nonlinear_walker_arch_full_imperfect', '', 'regression value (near the perfect arch\'s bifurcation)'),
    ('nonlinear_walker_arch', '', 'Walker 1969; the paper (ex. 2, k = 0)'),
    ('nonlinear_lee_frame', 'limit_min', 'Lee, Manuel & Rossow 1968 ("about −9.5", benchmarks.md (e))'),
    ('nonlinear_lee_frame', '', 'Lee, Manuel & Rossow 1968 (benchmarks.md (e))'),
    ('nonlinear_arch_pressure_kerr_soifer', 'limit_min', 'independent model (benchmarks.md ex. 4)'),
    ('nonlinear_arch_pressure_kerr_soifer', '', 'range of Kerr & Soifer 1969, Carnoy 1980, Sun & Natori 1996, the paper'),
    ('nonlinear_ring_full_double_bifurcation', '', 'Timoshenko & Gere 1961: 3EI/R³ at 16 elements a quarter (the quarter ring at that mesh)'),
    ('nonlinear_ring_pressure_follower', '', 'Timoshenko & Gere 1961 §7.5: 3EI/R³'),
    ('nonlinear_ring_pressure_fixed', '', 'Timoshenko & Gere 1961 §7.5: 4EI/R³'),
    ('contact_ex1_ring_rigid_cavity', 'at lambda', 'Table 2 of the paper: Pian & Bucciarelli / the paper (±1.5°)'),
    ('contact_ex1_ring_rigid_cavity', 's_contact_1', 'Pian & Bucciarelli 1967 24.6°, the paper 24.7°'),
    ('contact_ex1_ring_rigid_cavity', '', 'Pian & Bucciarelli 1967; the paper'),
    ('contact_ex1_ring_springs_k1e9', '', 'rigid limit, independent model N = 50 (benchmarks.md)'),
    ('contact_ex1_ring_springs', '', 'independent model N = 50 (benchmarks.md)'),
    ('contact_ex2', '', 'the paper §6.2'),
    ('contact_ex3', 'contact_lost', 'the paper\'s figure (≈ 30)'),
    ('contact_ex3', '', 'the paper §6.3'),
    ('contact_ex4', 'at w6_over_h', 'independent model N = 120 (benchmarks.md)'),
    ('contact_ex4', 'contact_start', 'the paper / benchmarks.md'),
    ('contact_ex4', '', 'the paper, Table 3'),
    ('members_timoshenko_column', '', 'Engesser: Timoshenko & Gere 1961 §2.13, P_E/(1 + P_E/κGA)'),
    ('members_timoshenko', '', 'closed form: w = PL³/3EI + PL/κGA, θ = PL²/2EI'),
    ('members_spring_base_column', '', 'Timoshenko & Gere 1961 ch. 2: αL tan αL = kL/EI'),
    ('members_hinge', '', 'closed form (statics of the hinge, then cantilever and simple span)'),
    ('members_joint_moment_limit_ring', '', 'Neal 1977, mechanism method: P_c = 4 MY/R'),
    ('members_joint_moment_limit_collapse', '', 'statics: P_c = MY/b'),
    ('members_joint_moment_limit', '', 'closed form in the deck (cantilever halves, joint at MY)'),
    ('members_spring_joint', '', 'closed form: w = PL³/3EI + Pb²/k, θ = PL²/2EI + Pb/k'),
    ('obstacle_column_against_step', '', 'hand solution in the deck (propped cantilever)'),
    ('pasternak_bonded_infinite_beam_kerr', '', 'infinite beam on a bonded Pasternak bed (theory.md §3.10): w(0) ='),
    ('pasternak_half_beam_symmetry_plane_kerr', '', 'the same closed form, half beam (theory.md §3.10): w(0) ='),
    ('pasternak_strut_bifurcation', '', 'min_m (m²π²EI/L² + G_p + KL²/(m²π²)) (theory.md §3.10)'),
    ('pasternak_bed_above', '', 'the bed below\'s values (the problem upside down)'),
    ('contact_tangential_bonded_bar', '', 'P coth(βL)/(EA β), β² = K_t/EA (theory.md §3.8)'),
    ('obstacle_cantilever_on_ellipse', '', 'hand solution in the deck (reaction along the normal)'),
]

# published values behind a range or a rounded reference: uniarc's value against each of them
REFERENCE_SETS = {
    ('nonlinear_arch_pressure_kerr_soifer', 'λ at limit_max'): [
        ('the paper', 2.2682), ('Sun & Natori 1996', 2.2784), ('Carnoy 1980', 2.2659),
        ('Kerr & Soifer 1969', 2.2613)],
    ('nonlinear_arch_pressure_kerr_soifer', 'w_crown_over_h at limit_max'): [
        ('the paper', 0.8514), ('Sun & Natori 1996', 0.8702), ('Carnoy 1980', 0.8605),
        ('Kerr & Soifer 1969', 0.8508)],
    ('contact_ex1_ring_rigid_cavity', 'λ at limit_max'): [
        ('Pian & Bucciarelli 1967', 81.5), ('Stein & Wriggers 1984', 79.9), ('Kodikara & Moore 1992', 81.7),
        ('the paper', 81.5)],
    ('contact_ex1_ring_rigid_cavity', 's_contact_1 (path) at limit_max'): [
        ('Pian & Bucciarelli 1967', 24.6), ('the paper', 24.7), ('Stein & Wriggers 1984', 24.0)],
    ('contact_ex1_ring_rigid_cavity', 's_contact_1 at lambda = 34'): [('Pian', 32.9), ('the paper', 32.2)],
    ('contact_ex1_ring_rigid_cavity', 's_contact_1 at lambda = 57'): [('Pian', 30.1), ('the paper', 28.4)],
    ('contact_ex1_ring_rigid_cavity', 's_contact_1 at lambda = 62 (2nd time)'): [('Pian', 23.9), ('the paper', 22.6)],
    ('contact_ex1_ring_rigid_cavity', 's_contact_1 at lambda = 28 (2nd time)'): [('Pian', 27.2), ('the paper', 26.1)],
}


def source_of(test, label):
    for prefix, part, text in SOURCES:
        if test.startswith(prefix) and part in label:
            return text
    return 'see the test\'s comment in tests/regression/CMakeLists.txt'


# --- evaluating the expectations of one test --------------------------------------------------------
def expected_parts(text):
    """(reference text, tolerance text, value or None, low, high)."""
    if '..' in text:
        low, high = sorted(float(x) for x in text.split('..'))
        return f'{low:g} – {high:g}', 'range', None, low, high
    value, tolerance = (float(x) for x in text.split(':'))
    shown = f'{tolerance * 100:g} %' if tolerance >= 1e-4 else f'{tolerance:g} (rel.)'
    return f'{value:.10g}', shown, value, value - tolerance * abs(value), value + tolerance * abs(value)


def numeric(test, label, got, expected):
    reference, tolerance, value, low, high = expected_parts(expected)
    error = abs(got - value) / abs(value) if value not in (None, 0.0) and got is not None else None
    ok = got is not None and low <= got <= high
    return {'test': test, 'label': label, 'reference': reference, 'tolerance': tolerance, 'value': got,
            'error': error, 'ok': ok, 'source': source_of(test, label)}


def at_event_step(names, rows, position, column):
    steps = [row[0] for row in rows]
    after = next((i for i, step in enumerate(steps) if step >= position), len(steps) - 1)
    before = max(after - 1, 0)
    span = steps[after] - steps[before]
    t = (position - steps[before]) / span if span > 0 else 0.0
    index = names.index(column)
    return rows[before][index] + t * (rows[after][index] - rows[before][index])


def evaluate(test, result):
    """Numeric rows and other checks (text, ok) of one regression test."""
    name, args = test['name'], test['args']
    numbers, checks = [], []
    if result['code'] != args.expect_exit:
        checks.append((f'uniarc exit code {result["code"]}, expected {args.expect_exit}: {result["stderr"][-300:]}', False))
        return numbers, checks
    for text in args.expect_stderr:
        checks.append((f'stderr has "{text}"', text in result['stderr']))
    if args.expect_exit != 0 and not os.path.isfile(result['path']):   # refused before its first step
        return numbers, checks
    names, rows = read_table(result['path'])
    for expectation in args.expect:
        column, expected = expectation.split('=', 1)
        numbers.append(numeric(name, f'{column} (final state)', rows[-1][names.index(column)], expected))
    for expectation in args.expect_row_where:
        where, rest = expectation.split(':', 1)
        key, target = where.split('=', 1)
        occurrence = 1
        if '#' in target:
            target, occurrence = target.split('#')
            occurrence = int(occurrence)
        column, expected = rest.split('=', 1)
        row, problem = value_where(names, rows, key, float(target), args.where_exact, occurrence)
        label = f'{column} at {key} = {target}' + (f' ({occurrence}{"nd" if occurrence == 2 else "th"} time)' if occurrence > 1 else '')
        numbers.append(numeric(name, label, None if problem else row[names.index(column)], expected))
    for expectation, is_max in [(e, True) for e in args.expect_max] + [(e, False) for e in args.expect_min]:
        column, bound = expectation.split('>=' if is_max else '<=')
        values = [row[names.index(column)] for row in rows]
        extreme = max(values) if is_max else min(values)
        ok = extreme >= float(bound) if is_max else extreme <= float(bound)
        checks.append((f'{"largest" if is_max else "smallest"} {column} along the path {extreme:.6g} '
                       f'(required {"≥" if is_max else "≤"} {bound})', ok))
    for expectation in args.expect_all:
        if '>=' in expectation:   # COLUMN>=VALUE: a lower bound at every step
            column, bound = expectation.split('>=')
            smallest = min(row[names.index(column)] for row in rows)
            checks.append((f'{column} at every step ≥ {bound} (smallest {smallest:.2e})', smallest >= float(bound)))
            continue
        column, bound = expectation.split('<=')
        largest = max(row[names.index(column)] for row in rows)
        checks.append((f'{column} at every step ≤ {bound} (largest {largest:.2e})', largest <= float(bound)))
    for column in args.expect_snap_back:
        c = [row[names.index(column)] for row in rows]
        lam = [row[names.index('lambda')] for row in rows]
        turns = [i for i in range(1, len(rows) - 1) if c[i - 1] < c[i] > c[i + 1] and lam[i - 1] > lam[i] > lam[i + 1]]
        text = (f'snap-back: {column} has a maximum {c[turns[0]]:.4f} at λ = {lam[turns[0]]:.4g} with λ falling through it'
                if turns else f'snap-back in {column}: not found')
        checks.append((text, bool(turns)))
    crit_names, events = read_events(result['crit']) if os.path.isfile(result['crit']) else ([], [])
    for expectation in args.expect_crit:
        event, expected = expectation.split('=', 1)
        kind, k = split_event(event)
        found = find_event(events, kind, k)
        label = f'λ at {kind}' + (f' #{k}' if k > 1 else '')
        numbers.append(numeric(name, label, found[crit_names.index('lambda')] if found else None, expected))
    for expectation in args.expect_crit_column:
        left, expected = expectation.split('=', 1)
        event, column = left.rsplit(':', 1)
        kind, k = split_event(event)
        found = find_event(events, kind, k)
        numbers.append(numeric(name, f'{column} at {kind}', found[crit_names.index(column)] if found else None, expected))
    for expectation in args.expect_crit_path:
        left, expected = expectation.split('=', 1)
        event, column = left.rsplit(':', 1)
        kind, k = split_event(event)
        found = find_event(events, kind, k)
        value = at_event_step(names, rows, found[crit_names.index('step')], column) if found else None
        numbers.append(numeric(name, f'{column} (path) at {kind}', value, expected))
    for expectation in args.expect_crit_count:
        kind, count = expectation.split('=')
        found = sum(1 for event_kind, _ in events if event_kind == kind)
        checks.append((f'{found} `{kind}` event(s) in STEM.crit (required {count})', found == int(count)))
    for expectation in args.expect_crit_before:
        first, second = (split_event(x) for x in expectation.split('<'))
        a, b = find_event(events, *first), find_event(events, *second)
        ok = a is not None and b is not None and a[0] < b[0]
        text = (f'`{first[0]}` (step {a[0]:.3f}, λ = {a[1]:.6g}) before `{second[0]}` (step {b[0]:.3f}, λ = {b[1]:.6g})'
                if a and b else f'`{first[0]}` before `{second[0]}`: an event is missing')
        checks.append((text, ok))
    return numbers, checks


# --- the report's sections -----------------------------------------------------------------------------
SECTIONS = [
    ('The paper\'s examples: unilateral contact', [
        ('Ex. 1 — ring in a rigid or elastic cavity', 'contact_ex1',
         'Deck `input/ring_rigid_cavity.inp`: thin ring (R/t = 100) in a tensionless circular cavity of the '
         'same radius under its self-weight, half ring, λ = K = pR³/EI. k = 0 is the exactly rigid cavity, '
         'k > 0 discrete radial springs k EI/R³ per node (the paper\'s elastic cavity). s_contact_1 is the '
         'separation angle φ in degrees.',
         ['ex1_path.png', 'ex1_phi.png', 'ex1_shapes.png']),
        ('Ex. 2 — Walker\'s arch on a tensionless foundation below', 'contact_ex2',
         'Deck `input/arch_foundation_below.inp`: Walker\'s pinned shallow arch (R/h = 500, half-opening 10°), '
         'crown load, Winkler foundation on the concave side, k = K_f R⁴/EI, half arch; λ = K = PR²/EI. '
         'The path of `input/walker_arch.inp` (no foundation) lies on the k = 0 path all along and is '
         'drawn over it, thin with open circles: a foundation of zero stiffness changes nothing.',
         ['ex2_paths.png', 'ex2_shapes.png']),
        ('Ex. 3 — the same arch under a foundation above', 'contact_ex3',
         'Deck `input/arch_foundation_above.inp`: the foundation on the convex side, so a central region '
         'separates under the load.',
         ['ex3_paths.png']),
        ('Ex. 4 — clamped arch under pressure meeting a flat surface', 'contact_ex4',
         'Deck `input/arch_pressure_flat.inp`: clamped shallow arch (λ_s = 10), fixed-direction radial '
         'pressure, λ = K = p h R²/EI, rigid plane at a = gap·h below the crown; w6_over_h is the '
         'deflection of the θ = −6° point (the paper\'s Fig. 13).',
         ['ex4_paths.png', 'ex4_shapes.png']),
    ]),
    ('Classic nonlinear problems', [
        ('Cantilever elastica, perpendicular tip load', 'nonlinear_elastica',
         'Deck `tests/regression/decks/elastica_tip_load.inp`, load control landing exactly on the '
         'tabulated loads PL²/EI.', ['elastica.png']),
        ('Euler columns', 'nonlinear_euler',
         'Decks `tests/regression/decks/euler_*.inp`: the critical load is the `bifurcation` of STEM.crit '
         '(a negative pivot appears on the straight path).', []),
        ('Walker\'s shallow arch, crown load, pinned ends (ex. 2 with k = 0)', 'nonlinear_walker',
         'Decks `input/walker_arch.inp` (half arch) and `tests/regression/decks/walker_arch_full.inp` '
         '(whole arch, perfect and with a small horizontal crown load).', ['walker.png']),
        ('Lee\'s frame — snap-back', 'nonlinear_lee',
         'Deck `tests/regression/decks/lee_frame.inp`, arc length through the whole path.', ['lee.png']),
        ('Kerr & Soifer\'s arch under radial pressure, no surface', 'nonlinear_arch_pressure',
         'Deck `input/arch_pressure_free.inp` (ex. 4 without the surface).', ['kerr_soifer.png']),
        ('Ring under uniform external pressure', 'nonlinear_ring_',
         'Decks `tests/regression/decks/ring_pressure_{follower,fixed}.inp`, quarter ring with double '
         'symmetry; the critical load is the `bifurcation` of the perfect ring. '
         '`tests/regression/decks/ring_full_pressure_follower.inp`: the whole ring, whose two oval modes '
         'buckle together (a double eigenvalue), against the quarter ring of the same element size.', []),
    ]),
    ('Linear closed forms', [
        ('Straight members under nodal loads', 'linear_',
         'Cubic Hermite elements reproduce the nodal displacements of straight prismatic members under '
         'nodal loads exactly, so only round-off separates uniarc from the closed form.', []),
    ]),
    ('Static analysis with contact, and loads (issue 13)', [
        ('Static analysis with contact: the linear contact LCP', 'static_contact',
         'Decks `tests/regression/decks/static_*.inp` under `*STATIC`: the structure and its unilateral '
         'contacts as one LCP at λ = 1 (docs/theory.md §3.6).', []),
        ('Temperature, settlement, self-weight, depth-varying pressure', 'loads_',
         'Decks `tests/regression/decks/thermal_*.inp`, `settlement_two_span.inp`, '
         '`static_heavy_beam_bonded_winkler.inp`, `ring_hydrostatic.inp`; each deck\'s comment gives its '
         'closed form.', []),
    ]),
    ('Foundations and soil springs (issue 16)', [
        ('The Pasternak (two-parameter) bed', ('pasternak_', 'static_stiff_footing_'),
         'docs/theory.md §3.10. The infinite beam on a bonded bed (Kerr 1964) and on a tensionless bed '
         '(the closed form derived in §3.10: contact half-length a from U\'(a) = 0, no concentrated reaction '
         'at the contact edge), the strut\'s bifurcation on a bonded bed, an independent finite-difference '
         'solution of the tensionless beam, G_p = 0 against Winkler\'s bed file for file, the rigid footing\'s '
         'closed forms. Tests run by their own scripts are listed with what those scripts print.', []),
        ('Tangential springs of a foundation', ('contact_tangential_', 'lining_bedded_'),
         'docs/theory.md §3.8: a bar on a bonded tangential bed (P coth(βL)/(EA β)), springs only where the '
         'radial contact is closed, their release along a path, *STATIC against *PATH, and the field deck '
         'of a bedded segmental lining.', []),
        ('Elastic–plastic soil springs and beds', ('plastic_',),
         'docs/theory.md §3.9: springs and beds with a bearing limit QU and an uplift limit TU, against the '
         'closed forms of their load histories, limit loads (q_u × contact length) and an independent '
         'active-set solution of a beam on a yielding bed (plastic_check.py).', []),
    ]),
    ('Members and obstacles', [
        ('Timoshenko beams, hinges and rotational-spring joints', 'members_',
         'Decks `tests/regression/decks/{timo_cantilever,hinge_gerber,spring_joint,timoshenko_column,'
         'spring_base_column}.inp` '
         '(docs/theory.md §1.10): the Timoshenko element and the jointed beams are exact for nodal loads, so '
         'the linear cases meet their closed forms to round-off; the column is corotational. Joints with a '
         'moment limit (docs/theory.md §1.11): decks `joint_moment_limit_{beam,collapse,ring}.inp`, traced on '
         'the corotational path, so their closed forms (small displacements) hold to the geometry\'s effect.', []),
        ('Obstacles of any shape: ellipse and polyline', 'obstacle_',
         'Decks `tests/regression/decks/{ring_circle_cavity,ring_oval_cavity,column_step,'
         'cantilever_on_ellipse}.inp` (docs/theory.md §3.7). The ellipse with a = b is compared with the '
         'circle over the whole path (a numeric diff, not listed here).', []),
    ]),
]

# mesh-convergence studies: (title, deck, defines, parameter, meshes, quantity, reference, source)
CONVERGENCE = [
    ('Ex. 1, rigid cavity: K_cr', 'input/ring_rigid_cavity.inp', [], 'n', [50, 100, 200, 400],
     ('crit', 'limit_max', 'lambda'), 81.5, 'Pian & Bucciarelli 1967; the paper'),
    ('Ex. 1, rigid cavity, fine meshes (every node a contact candidate; the contact LCP at scale): K_cr',
     'input/ring_rigid_cavity.inp', [], 'n', [500, 1000, 2000, 4000],
     ('crit', 'limit_max', 'lambda'), 81.5, 'Pian & Bucciarelli 1967; the paper'),
    ('Ex. 2, k = 1e4: K_lim', 'input/arch_foundation_below.inp', ['k=1e4'], 'n', [10, 20, 40, 80],
     ('crit', 'limit_max', 'lambda'), 83.4, 'the paper §6.2'),
    ('Ex. 4, a/h = 4.98: first contact K', 'input/arch_pressure_flat.inp', ['gap=4.98'], 'n', [15, 30, 60, 120],
     ('crit', 'contact_start', 'lambda'), 0.67, 'the paper'),
    ('Kerr & Soifer arch: K_cr', 'input/arch_pressure_free.inp', [], 'n', [15, 30, 60, 120],
     ('crit', 'limit_max', 'lambda'), 2.2682, 'the paper, Table 3'),
    ('Walker arch (half): K_lim', 'input/walker_arch.inp', [], 'n', [10, 20, 40, 80],
     ('crit', 'limit_max', 'lambda'), 76.21, 'Walker 1969'),
    ('Lee\'s frame: first limit', 'tests/regression/decks/lee_frame.inp', [], 'n', [5, 10, 20, 40],
     ('crit', 'limit_max', 'lambda'), 18.575, 'Lee et al. 1968 (middle of 18.56–18.59)'),
    ('Euler column, pinned–pinned', 'tests/regression/decks/euler_pinned_pinned.inp', [], 'n', [5, 10, 20, 40],
     ('crit', 'bifurcation', 'lambda'), math.pi ** 2, 'Timoshenko & Gere 1961'),
    ('Ring, follower pressure', 'tests/regression/decks/ring_pressure_follower.inp', [], 'n', [5, 10, 20, 40],
     ('crit', 'bifurcation', 'lambda'), 3.0, 'Timoshenko & Gere 1961 §7.5'),
]

# ex. 1 with springs, N = 50 (the paper's mesh): benchmarks.md's independent model (OpenSees, N = 50)
SWEEP_VALUES = ['1e3', '1e4', '1e5', '1.8e5', '1e6', '1e7', '1e9', '0']
SWEEP_REFERENCE = {'1e3': 35.2, '1e4': 66.0, '1e5': 80.8, '1.8e5': 81.9, '1e6': 83.2, '1e7': 83.4, '0': 83.47}

# --- run everything ----------------------------------------------------------------------------------------
log(f'{len(tests)} regression tests, {len(convergence_tests)} convergence test(s), '
    f'{sum(len(c[4]) for c in CONVERGENCE)} convergence runs, {len(SWEEP_VALUES)} sweep runs, {jobs} at a time')
job_list = [(t['name'], t['deck'], os.path.join(work, t['name']), t['args'].define) for t in tests]
for c in convergence_tests:
    for n in c['args'].meshes:
        job_list.append(((c['name'], n), c['args'].deck, os.path.join(work, f'{c["name"]}_{n}'),
                         [f'{c["args"].parameter}={n}']))
for number, (title, deck, defines, parameter, meshes, *_ ) in enumerate(CONVERGENCE):
    for n in meshes:
        job_list.append((('convergence', number, n), os.path.join(root, deck),
                         os.path.join(work, f'convergence_{number}_{parameter}{n}'), defines + [f'{parameter}={n}']))
results = run_all(job_list)
# the script tests of the parts whose checks are mostly scripts' (the media of issue 16)
SCRIPT_PARTS = ('Foundations and soil springs (issue 16)',)
script_tests = collect_script_tests(tuple(p for part, cases in SECTIONS if part in SCRIPT_PARTS
                                          for _, prefix, *_ in cases
                                          for p in ((prefix,) if isinstance(prefix, str) else prefix)))


def run_script(test):
    if test['unresolved']:
        return {'code': None, 'output': f'not run: unresolved {" ".join(test["unresolved"])}'}
    done = subprocess.run(test['command'], capture_output=True, text=True, cwd=os.path.join(root, 'tests', 'regression'))
    return {'code': done.returncode, 'output': (done.stdout + done.stderr).strip()}


log(f'{len(script_tests)} tests run by their own scripts')
with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
    script_results = dict(zip([t['name'] for t in script_tests], pool.map(run_script, script_tests)))
sweep_dir = os.path.join(work, 'sweep')
shutil.rmtree(sweep_dir, ignore_errors=True)
subprocess.run(['bash', os.path.join(root, 'scripts', 'sweep.sh'), os.path.join(root, 'input', 'ring_rigid_cavity.inp'),
                'k', *SWEEP_VALUES, '-D', 'n=50', '--label', '0=rigid', '--uniarc', uniarc, '--out', sweep_dir],
               check=True, capture_output=True, text=True)
sweep_folder = os.path.join(sweep_dir, 'sweep_ring_rigid_cavity_k')
shutil.copy(os.path.join(sweep_folder, 'sweep.png'), os.path.join(image_dir, 'ex1_sweep_k.png'))

# --- pictures ----------------------------------------------------------------------------------------------
def plot_path(image, files, x, labels=(), extra=()):
    command = ['bash', os.path.join(root, 'scripts', 'plot_path.sh'), '-x', x, '-o', os.path.join(image_dir, image), *extra]
    for label in labels:
        command += ['-l', label]
    subprocess.run(command + files, check=True, capture_output=True, text=True)


def plot_shapes(image, shape, extra=()):
    subprocess.run(['bash', os.path.join(root, 'scripts', 'plot_shapes.sh'), '-o', os.path.join(image_dir, image),
                    *extra, shape], check=True, capture_output=True, text=True)


def defines_of(test):
    return dict(d.split('=', 1) for d in next(t for t in tests if t['name'] == test)['args'].define)


def label_of(test, parameter, default):
    defines = defines_of(test)
    mesh = f', n = {defines["n"]}' if 'n' in defines else ''
    return (f'{parameter} = {defines[parameter]}' if parameter in defines else default) + mesh


def path_files(prefix):
    names = [t['name'] for t in tests if t['name'].startswith(prefix) and results[t['name']]['code'] == 0]
    return names, [results[n]['path'] for n in names]


made = set()
try:
    names, files = path_files('contact_ex1')
    plot_path('ex1_path.png', files, 'v_crown', [label_of(n, 'k', 'rigid cavity (deck mesh)') for n in names],
              ['-t', 'Ex. 1: ring in a cavity, crown deflection v/R'])
    plot_path('ex1_phi.png', [results['contact_ex1_ring_rigid_cavity']['path']], 's_contact_1', ['rigid cavity'],
              ['-t', 'Ex. 1: separation angle (s_contact_1, degrees) along the path'])
    plot_shapes('ex1_shapes.png', results['contact_ex1_ring_rigid_cavity']['shape'], ['-f', '5', '-t', 'Ex. 1, rigid cavity'])
    names, files = path_files('contact_ex2')
    walker = results['nonlinear_walker_arch_half']['path']
    plot_path('ex2_paths.png', [walker] + files, 'w_over_rise', ['walker_arch.inp (no foundation), n = 40'] +
              [label_of(n, 'k', '') for n in names], ['-t', 'Ex. 2: foundation below, crown deflection / rise'])
    plot_shapes('ex2_shapes.png', results['contact_ex2_arch_below_k1e4']['shape'], ['-F', '-t', 'Ex. 2, k = 1e4'])
    names, files = path_files('contact_ex3')
    plot_path('ex3_paths.png', files, 'w_over_rise', [label_of(n, 'k', '') for n in names],
              ['-C', '-t', 'Ex. 3: foundation above, crown deflection / rise'])
    names, files = path_files('contact_ex4')
    plot_path('ex4_paths.png', files, 'w6_over_h', [label_of(n, 'gap', '') for n in names],
              ['-C', '-t', 'Ex. 4: deflection of the -6 deg point / h (the paper\'s Fig. 13)'])
    plot_shapes('ex4_shapes.png', results['contact_ex4_arch_flat_gap4p98']['shape'], ['-F', '-t', 'Ex. 4, a/h = 4.98'])
    plot_path('elastica.png', [results['nonlinear_elastica_mattiasson']['path']], 'w_over_L', ['w/L'],
              ['-t', 'Cantilever elastica: PL^2/EI against the tip deflection w/L'])
    names, files = path_files('nonlinear_walker')
    plot_path('walker.png', files, 'w_over_rise',
              [{'nonlinear_walker_arch_half': 'half arch', 'nonlinear_walker_arch_full_bifurcation': 'whole arch, perfect',
                'nonlinear_walker_arch_full_imperfect': 'whole arch, horizontal crown load'}.get(n, n) + (
                  f', n = {defines_of(n)["n"]}' if 'n' in defines_of(n) else '') for n in names],
              ['-t', 'Walker\'s arch, k = 0: crown deflection / rise'])
    plot_path('lee.png', [results['nonlinear_lee_frame_snap_back']['path']], 'v_over_L', ['v/L of the load point'],
              ['-t', 'Lee\'s frame: PL^2/EI against the load point\'s deflection'])
    plot_path('kerr_soifer.png', [results['nonlinear_arch_pressure_kerr_soifer']['path']], 'w_crown_over_h',
              ['n = 60'], ['-t', 'Kerr & Soifer\'s arch, no surface'])
except subprocess.CalledProcessError as error:
    log(f'a plot failed: {error.cmd}\n{error.stderr}')
for image in os.listdir(image_dir):
    made.add(image)

# --- evaluate --------------------------------------------------------------------------------------------
evaluated = {t['name']: evaluate(t, results[t['name']]) for t in tests}


def fmt(x, digits=6):
    return '—' if x is None else f'{x:.{digits}g}'


def err(x):
    return '—' if x is None else f'{x:.1e}'


lines = []
out = lines.append
version = subprocess.run([uniarc, '--version'], capture_output=True, text=True).stdout.strip()
total_numbers = sum(len(n) for n, _ in evaluated.values())
total_checks = sum(len(c) for _, c in evaluated.values())
failed_numbers = [(r['test'], r['label']) for n, _ in evaluated.values() for r in n if not r['ok']]
failed_checks = [(name, text) for name, (_, c) in evaluated.items() for text, ok in c if not ok]
failed_checks += [(t['name'], f'{t["checker"]} exited {script_results[t["name"]]["code"]}')
                  for t in script_tests if script_results[t['name']]['code'] != 0]
total_checks += len(script_tests)

out('# uniarc — verification report')
out('')
out(f'*Generated by `scripts/verify.sh` from uniarc\'s own runs — do not edit by hand, run the script. '
    f'{version}, source `{revision or "unknown"}`, '
    f'{"Release build" if build_type == "Release" else "uniarc given with --uniarc"}, '
    f'{datetime.date.today().isoformat()}.*')
out('')
out('Every check of the regression tests (`tests/regression/CMakeLists.txt`: the decks, the `-D` '
    'overrides, the references and the tolerances are read from there) is run again below and listed '
    'with its reference, where the reference comes from, uniarc\'s value and the relative error '
    '|uniarc − reference| / |reference|. The tolerance is the test\'s; "range" means the test asks for a '
    'value inside the spread of the published values. λ is each deck\'s nondimensional load. Limit points '
    'and bifurcations are rows of STEM.crit, located between steps; values "(path)" and "at key = value" '
    'are path columns interpolated linearly. Each section names its problem and the sources of its '
    'reference values. Run the same checks as tests with `ctest -L regression`.')
out('')
out(f'**Result: {total_numbers - len(failed_numbers)} of {total_numbers} reference values and '
    f'{total_checks - len(failed_checks)} of {total_checks} other checks pass** '
    f'({len(tests)} regression tests, {len(convergence_tests)} convergence tests, {len(script_tests)} '
    f'tests run by their own scripts, each one check).')
if failed_numbers or failed_checks:
    out('')
    out('Failing:')
    for test, label in failed_numbers + failed_checks:
        out(f'- `{test}`: {label}')
out('')

section_number = 0
for part, cases in SECTIONS:
    for title, prefix, text, images in cases:
        section_number += 1
        out(f'## {section_number}. {title}')
        out('')
        out(text)
        out('')
        names = [t['name'] for t in tests if t['name'].startswith(prefix)]
        rows = [r for n in names for r in evaluated[n][0]]
        if rows:
            out('| test | quantity | reference | source | uniarc | rel. err. | tolerance | |')
            out('|---|---|---|---|---|---|---|---|')
            for r in rows:
                defines = ', '.join(next(t for t in tests if t['name'] == r['test'])['args'].define)
                test_label = f'`{r["test"]}`' + (f' ({defines})' if defines else '')
                out(f'| {test_label} | {r["label"]} | {r["reference"]} | {r["source"]} | {fmt(r["value"], 7)} | '
                    f'{err(r["error"])} | {r["tolerance"]} | {"ok" if r["ok"] else "**FAIL**"} |')
            out('')
        sets = [(key, r) for r in rows for key in REFERENCE_SETS if key == (r['test'], r['label'])]
        if sets:
            out('Against each published value:')
            out('')
            out('| test | quantity | source | reference | uniarc | rel. err. |')
            out('|---|---|---|---|---|---|')
            for key, r in sets:
                for source, value in REFERENCE_SETS[key]:
                    error = abs(r['value'] - value) / abs(value) if r['value'] is not None else None
                    out(f'| `{r["test"]}` | {r["label"]} | {source} | {value:g} | {fmt(r["value"], 6)} | {err(error)} |')
            out('')
        checks = [(n, text, ok) for n in names for text, ok in evaluated[n][1]]
        if checks:
            out('Other checks:')
            out('')
            for n, text, ok in checks:
                out(f'- `{n}`: {text} — {"ok" if ok else "**FAIL**"}')
            out('')
        for c in [c for c in convergence_tests if c['name'].startswith(prefix)]:
            a = c['args']
            values = []
            for n in a.meshes:
                r = results[(c['name'], n)]
                names_, rows_ = read_table(r['path']) if r['code'] == 0 else ([], [])
                values.append(rows_[-1][names_.index(a.column)] if rows_ else None)
            out(f'Mesh convergence: `{c["name"]}` (deck `{os.path.relpath(a.deck, root)}`, '
                f'{source_of(c["name"], "")} {a.exact:.12g}). The discretisation (straight elements of a '
                f'curved member, a lumped bed) converges at a rate, so the test checks the observed order '
                f'and the Richardson value:')
            out('')
            out(f'| {a.parameter} | ' + ' | '.join(str(n) for n in a.meshes) + ' | Richardson |')
            out('|---|' + '---|' * (len(a.meshes) + 1))
            if None not in values:
                f1, f2, f3 = values[-3:]
                ratio = a.meshes[-1] / a.meshes[-2]
                order = math.log(abs((f1 - f2) / (f3 - f2))) / math.log(ratio)
                extrapolated = f3 + (f3 - f2) / (ratio ** order - 1.0)
                error = abs(extrapolated - a.exact) / abs(a.exact)
                out(f'| {a.column} | ' + ' | '.join(f'{v:.10g}' for v in values) + f' | {extrapolated:.12g} |')
                out(f'| rel. err. | ' + ' | '.join(err(abs(v - a.exact) / abs(a.exact)) for v in values) + f' | {err(error)} |')
                out('')
                ok = abs(order - a.order) <= a.order_tolerance and error <= a.rtol
                out(f'Observed order {order:.3f} (test: {a.order:g} ± {a.order_tolerance:g}); Richardson value '
                    f'{error:.1e} from the closed form (test: {a.rtol:g}) — {"ok" if ok else "**FAIL**"}.')
            else:
                out('| — | a run failed |')
            out('')
        scripted = [t for t in script_tests if t['name'].startswith(prefix)]
        if scripted:
            out('Checks by their own scripts (the test passes when its script exits 0; below, what the '
                'script prints: uniarc\'s values, the references and the tolerances):')
            out('')
            for t in scripted:
                r = script_results[t['name']]
                status = 'ok' if r['code'] == 0 else f'**FAIL** (exit {r["code"]})'
                out(f'- `{t["name"]}` — `{t["checker"]}`' + (f' on `{t["deck"]}`' if t['deck'] else '') +
                    f' — {status}')
                shown = [line.replace(root + os.sep, '') for line in r['output'].splitlines() if line.strip()]
                if len(shown) > 40:
                    shown = shown[:39] + [f'... ({len(shown) - 39} more lines)']
                if shown:
                    out('')
                    out('  ```')
                    for line in shown:
                        out('  ' + line.rstrip())
                    out('  ```')
            out('')
        for image in images:
            if image in made:
                out(f'![{title}: {os.path.splitext(image)[0]}](img/{image})')
                out('')

# the k sweep of ex. 1 (Fig. 6)
section_number += 1
out(f'## {section_number}. Ex. 1 with an elastic cavity: K_cr against k (the paper\'s Fig. 6)')
out('')
out('`scripts/sweep.sh input/ring_rigid_cavity.inp k ' + ' '.join(SWEEP_VALUES) + ' -D n=50 --label 0=rigid` — discrete '
    'radial springs k EI/R³ per node on the paper\'s mesh (50 elements on the half ring); k = 0 is the '
    'exactly rigid cavity, the k → ∞ limit. Reference: the independent model of benchmarks.md (OpenSees, '
    'the same definition and mesh); the paper gives these values only as a figure. K_cr must rise '
    'monotonically toward the rigid value, and very stiff springs must give the rigid limit without the '
    'penalty trouble the paper met above k = 1.2e7.')
out('')
out('| k | reference (independent model, N = 50) | uniarc K_cr | rel. err. | v/R at K_cr | φ = s_contact_1 at K_cr (°) | status |')
out('|---|---|---|---|---|---|---|')
tsv = [line.split('\t') for line in open(os.path.join(sweep_folder, 'sweep.tsv')).read().splitlines()]
header = tsv[0]
loads = []
for row in tsv[1:]:
    entry = dict(zip(header, row))
    load = float(entry['lambda_limit'])
    reference = SWEEP_REFERENCE.get(entry['value'])
    loads.append((entry['value'], load))
    error = abs(load - reference) / reference if reference and math.isfinite(load) else None
    out(f'| {entry["value"]}{" (rigid)" if entry["value"] == "0" else ""} | {reference if reference else "—"} | '
        f'{load:.6g} | {err(error)} | {float(entry["v_crown"]):.4g} | {float(entry["s_contact_1"]):.4g} | {entry["status"]} |')
out('')
springs = [l for v, l in loads if v != '0']
rigid = dict(loads).get('0')
monotone = all(a <= b for a, b in zip(springs, springs[1:]))
out(f'K_cr rises monotonically with k: {"yes" if monotone else "**no**"}; the stiffest springs '
    f'(k = {SWEEP_VALUES[-2]}) against the rigid cavity: relative difference '
    f'{abs(springs[-1] - rigid) / rigid:.1e}.')
out('')
out('![K_cr against k](img/ex1_sweep_k.png)')
out('')

# mesh convergence
section_number += 1
out(f'## {section_number}. Mesh convergence')
out('')
out('Straight corotational elements converge at second order in the element size for a curved member. '
    'Each row is a sequence of runs with `-D n=…` (n elements on the modelled part); the observed order '
    'comes from the three finest meshes, the extrapolated value from Richardson\'s formula with it. The '
    'regression tests use a mesh whose discretisation error is a fraction of their tolerance.')
out('')
for number, (title, deck, defines, parameter, meshes, quantity, reference, source) in enumerate(CONVERGENCE):
    values = []
    for n in meshes:
        r = results[('convergence', number, n)]
        value = None
        if r['code'] == 0 and os.path.isfile(r['crit']):
            crit_names, events = read_events(r['crit'])
            found = find_event(events, quantity[1], 1)
            value = found[crit_names.index(quantity[2])] if found else None
        values.append(value)
    out(f'**{title}** — deck `{deck}`' + (f' with {", ".join(defines)}' if defines else '') +
        f'; reference {reference:.6g} ({source}).')
    out('')
    out(f'| {parameter} | ' + ' | '.join(str(n) for n in meshes) + ' | Richardson |')
    out('|---|' + '---|' * (len(meshes) + 1))
    richardson, order = None, None
    if None not in values[-3:] and values[-1] != values[-2] and values[-2] != values[-3]:
        f1, f2, f3 = values[-3:]
        ratio = meshes[-1] / meshes[-2]
        order = math.log(abs((f1 - f2) / (f2 - f3))) / math.log(ratio)
        richardson = f3 + (f3 - f2) / (ratio ** order - 1.0) if order > 0 else None
    out('| value | ' + ' | '.join(fmt(v, 7) for v in values) + f' | {fmt(richardson, 7)} |')
    out('| rel. err. | ' + ' | '.join(err(None if v is None else abs(v - reference) / abs(reference)) for v in values)
        + f' | {err(None if richardson is None else abs(richardson - reference) / abs(reference))} |')
    out('')
    if order is not None:
        out(f'Observed order {order:.2f}.')
        out('')
elapsed = time.time() - float(start)
out('---')
out(f'{len(job_list) + len(SWEEP_VALUES)} uniarc runs in {elapsed:.0f} s on {jobs} core(s).')
open(output, 'w').write('\n'.join(lines) + '\n')
log(f'wrote {output} ({total_numbers - len(failed_numbers)}/{total_numbers} values, '
    f'{total_checks - len(failed_checks)}/{total_checks} checks pass) in {elapsed:.0f} s')
sys.exit(1 if failed_numbers or failed_checks else 0)
PYTHON
