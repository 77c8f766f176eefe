#!/usr/bin/env python3
"""Contact at pipeline scale: uniarc and OpenSees side by side on the same models.

Runs, for each model (ring in a tensionless Winkler foundation, free beam on a tensionless bed), each
size n (number of elements), each foundation variant (tensionless = contact LCP; bonded = the same
springs both ways, BILATERAL, no complementarity) and each program (uniarc; OpenSees through
openseespy), one whole run in its own process under `timeout` and `/usr/bin/time -v`, and prints a
Markdown table: wall time, peak resident memory, steps, Newton iterations, Lemke pivots (uniarc), the
number of springs in compression (in contact) at the last step and one tracked displacement; then the
ratio tensionless / bonded run time per program, and the agreement of the two programs.

Usage (from the repository root; see docs/benchmarks.md §4):

    python3 bench/contact_scale.py --uniarc build/uniarc --sizes 1000 -o out/contact_scale.md
    python3 bench/contact_scale.py --sizes 1000 10000 --with-1e5 --timeout 1800 -o out/cs.md

OpenSees is a benchmark peer only (pip install openseespy); without it, --programs uniarc.
"""

import argparse
import datetime
import json
import os
import platform
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import opensees_models  # noqa: E402  (parameters and geometry of the models; openseespy not imported)

DECKS = {
    'ring': os.path.join(HERE, 'decks', 'ring_in_winkler.inp'),
    'beam': os.path.join(HERE, 'decks', 'beam_on_tensionless_bed.inp'),
}
TRACKED = {'ring': 'uy_crown', 'beam': 'uy_lift'}
# Parameters that are structural in the decks and must not be passed with -D (the beam deck has one
# element set per phase of its m-element wave).
FIXED_IN_DECK = {'beam': {'m'}, 'ring': set()}
LARGE = 100000
STEPS = 30


def parse_time_v(path):
    """The peak RSS (kB) that GNU time -v reports, or None."""
    rss = None
    try:
        with open(path) as f:
            for line in f:
                if 'Maximum resident set size' in line:
                    rss = int(line.split(':')[-1])
    except OSError:
        pass
    return rss


def timed_run(command, timeout, workdir, label):
    """Run `command` under `timeout` and `/usr/bin/time -v`; return (rc, wall s, peak RSS kB, stdout,
    stderr). rc 124 (or 137 after the kill) means that the time limit was hit. The peak RSS that GNU
    time reports for `timeout` includes that of its child, the run itself (Linux rusage of a waited-for
    process tree). Without /usr/bin/time the same rusage is read with os.wait4."""
    time_file = os.path.join(workdir, label + '.time')
    wrapped = ['timeout', '--kill-after=10', '%g' % timeout] + command
    use_gnu_time = os.access('/usr/bin/time', os.X_OK)
    if use_gnu_time:
        wrapped = ['/usr/bin/time', '-v', '-o', time_file] + wrapped
    out_path = os.path.join(workdir, label + '.stdout')
    err_path = os.path.join(workdir, label + '.stderr')
    start = time.perf_counter()
    with open(out_path, 'w') as out_file, open(err_path, 'w') as err_file:
        proc = subprocess.Popen(wrapped, stdout=out_file, stderr=err_file)
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
    wall = time.perf_counter() - start
    rc = proc.returncode
    rss = parse_time_v(time_file) if use_gnu_time else usage.ru_maxrss
    with open(out_path) as f:
        out = f.read()
    with open(err_path) as f:
        err = f.read()
    return rc, wall, rss, out, err


def status_of(rc, steps, lam):
    if rc in (124, 137):
        return 'timeout'
    if rc != 0:
        return 'failed (exit %d)' % rc
    # ok when the full load is reached: 30 steps, or more where a step was cut and halved
    if steps < STEPS or abs(lam - 1.0) > 1e-9:
        return 'incomplete'
    return 'ok'


def read_path_file(directory, stem):
    """Rows of STEM.path (or of STEM.path.part when the run was stopped) as dicts."""
    for name in (stem + '.path', stem + '.path.part'):
        path = os.path.join(directory, name)
        if os.path.exists(path):
            with open(path) as f:
                lines = f.read().splitlines()
            if not lines:
                return []
            header = lines[0].split()
            rows = []
            for line in lines[1:]:
                if line.startswith('#'):
                    continue        # the provenance lines
                fields = line.split()
                if len(fields) != len(header):
                    break          # a row cut short by the kill
                rows.append(dict(zip(header, map(float, fields))))
            return rows
    return []


def bonded_deck(deck, workdir):
    """A copy of the deck with BILATERAL added to its *FOUNDATION card (same springs, no LCP)."""
    stem = os.path.splitext(os.path.basename(deck))[0] + '_bonded'
    target = os.path.join(workdir, stem + '.inp')
    done = 0
    with open(deck) as f, open(target, 'w') as g:
        for line in f:
            if re.match(r'\s*\*FOUNDATION\b', line, re.IGNORECASE):
                line = line.rstrip('\n') + ', BILATERAL\n'
                done += 1
            g.write(line)
    if done != 1:
        raise SystemExit('expected one *FOUNDATION card in %s, found %d' % (deck, done))
    return target, stem


def run_uniarc(binary, model, n, bonded, timeout, workdir):
    deck = DECKS[model]
    stem = os.path.splitext(os.path.basename(deck))[0]
    if bonded:
        deck, stem = bonded_deck(deck, workdir)
    label = 'uniarc_%s_%d_%s' % (model, n, 'bonded' if bonded else 'contact')
    outdir = os.path.join(workdir, label)
    command = [binary, deck, '-o', outdir, '-q', '-D', 'n=%d' % n]
    for name, value in opensees_models.DEFAULTS[model].items():
        if name not in FIXED_IN_DECK[model]:
            command += ['-D', '%s=%r' % (name, value)]
    rc, wall, rss, out, err = timed_run(command, timeout, workdir, label)
    rows = read_path_file(outdir, stem)
    steps_rows = [r for r in rows if r['step'] >= 1]
    last = rows[-1] if rows else {}
    steps = int(last.get('step', 0))
    lam = last.get('lambda', 0.0)
    result = {
        'program': 'uniarc', 'model': model, 'n': n, 'bonded': bonded, 'rc': rc, 'wall': wall,
        'rss_kb': rss, 'steps': steps, 'lambda': lam,
        'iterations': int(sum(r['iterations'] for r in steps_rows)),
        'lcp_pivots': int(sum(r['lcp_pivots'] for r in steps_rows)),
        'n_contact': int(last['n_contact']) if steps_rows else None,
        'n_springs': n if model == 'ring' else n + 1,
        'track': last.get(TRACKED[model]) if steps_rows else None,
        'status': status_of(rc, steps, lam),
        'message': err.strip().splitlines()[-1] if rc not in (0, 124, 137) and err.strip() else '',
    }
    return result


def run_opensees(model, n, bonded, system, timeout, workdir, python, test):
    label = 'opensees_%s_%d_%s_%s' % (model, n, 'bonded' if bonded else 'contact', system)
    command = [python, os.path.join(HERE, 'opensees_models.py'), '--model', model, '--n', str(n),
               '--system', system, '--steps', str(STEPS), '--test', test]
    if bonded:
        command.append('--bonded')
    rc, wall, rss, out, err = timed_run(command, timeout, workdir, label)
    data = None
    steps = 0
    for line in out.splitlines():
        if line.startswith('{'):
            data = json.loads(line)
        elif line.startswith('step '):
            steps = int(line.split()[1])
    result = {
        'program': 'OpenSees (%s)' % system, 'model': model, 'n': n, 'bonded': bonded, 'rc': rc,
        'wall': wall, 'rss_kb': rss, 'steps': data['steps'] if data else steps,
        'lambda': data['lambda'] if data else float('nan'),
        'iterations': data['iterations'] if data else None, 'lcp_pivots': None,
        'n_contact': data['n_contact'] if data else None,
        'n_springs': data['n_springs'] if data else (n if model == 'ring' else n + 1),
        'track': data['track'] if data else None, 'message': '',
    }
    if data and data['failed']:
        result['status'] = 'no convergence at step %d' % (data['steps'] + 1)
    elif data is None and rc not in (124, 137):
        result['status'] = 'failed (exit %d)' % rc
        result['message'] = err.strip().splitlines()[-1] if err.strip() else ''
    else:
        result['status'] = status_of(rc, result['steps'], result['lambda'] if data else 0.0)
    return result


def fmt(value, spec):
    if value is None:
        return '—'
    return format(value, spec)


def markdown(results, baseline, header_lines):
    out = list(header_lines)
    out.append('')
    out.append('| model | n | foundation | program | status | steps | wall s | peak RSS MB | iterations '
               '| Lemke pivots | springs in compression / all | tracked at λ = 1 |')
    out.append('|---|---:|---|---|---|---:|---:|---:|---:|---:|---:|---|')
    for r in results:
        contact = '—' if r['n_contact'] is None else '%d / %d' % (r['n_contact'], r['n_springs'])
        track = '—' if r['track'] is None else '%s = %.6g' % (TRACKED[r['model']], r['track'])
        # A run stopped by the time limit has done at least the steps found in its output (uniarc
        # buffers its path file, so the rows of the last steps may be missing).
        steps = ('≥ %d' if r['status'] == 'timeout' else '%d') % r['steps']
        out.append('| %s | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |' % (
            r['model'], r['n'], 'bonded' if r['bonded'] else 'tensionless', r['program'], r['status'],
            steps, fmt(r['wall'], '.2f'), fmt(r['rss_kb'] / 1024.0 if r['rss_kb'] else None, '.0f'),
            fmt(r['iterations'], 'd'), fmt(r['lcp_pivots'], 'd'), contact, track))
    out.append('')
    out.append('Tensionless / bonded run time (target for uniarc: ≤ 3):')
    out.append('')
    out.append('| model | n | program | tensionless s | bonded s | ratio |')
    out.append('|---|---:|---|---:|---:|---:|')
    keyed = {(r['model'], r['n'], r['program'], r['bonded']): r for r in results}
    for (model, n, program, bonded), r in keyed.items():
        if bonded:
            continue
        b = keyed.get((model, n, program, True))
        if b is None:
            continue
        ok = r['status'] == 'ok' and b['status'] == 'ok'
        ratio = '%.2f' % (r['wall'] / b['wall']) if ok else '— (%s / %s)' % (r['status'], b['status'])
        out.append('| %s | %d | %s | %.2f | %.2f | %s |' % (model, n, program, r['wall'], b['wall'], ratio))
    out.append('')
    out.append('Agreement at λ = 1 (uniarc against each OpenSees run of the same case):')
    out.append('')
    out.append('| model | n | foundation | against | Δ springs in compression | tracked, relative difference |')
    out.append('|---|---:|---|---|---:|---:|')
    for r in results:
        if r['program'] != 'uniarc' or r['status'] != 'ok':
            continue
        for o in results:
            if (o['program'].startswith('OpenSees') and o['model'] == r['model'] and o['n'] == r['n']
                    and o['bonded'] == r['bonded'] and o['status'] == 'ok'):
                rel = abs(r['track'] - o['track']) / max(abs(o['track']), 1e-300)
                out.append('| %s | %d | %s | %s | %+d | %.1e |' % (
                    r['model'], r['n'], 'bonded' if r['bonded'] else 'tensionless', o['program'],
                    r['n_contact'] - o['n_contact'], rel))
    if baseline is not None:
        out.append('')
        out.append('OpenSees rows include the Python interpreter: `%s -c "import openseespy.opensees"` '
                   'alone takes %.2f s and %.0f MB here.' % baseline)
    messages = [r for r in results if r['message']]
    if messages:
        out.append('')
        out.append('Messages of failed runs:')
        out.append('')
        for r in messages:
            out.append('- %s %s n=%d %s: `%s`' % (r['program'], r['model'], r['n'],
                                                  'bonded' if r['bonded'] else 'tensionless', r['message']))
    return '\n'.join(out) + '\n'


def main():
    parser = argparse.ArgumentParser(
        description='uniarc and OpenSees side by side on two contact models (docs/benchmarks.md §4)')
    parser.add_argument('--uniarc', default=os.path.join(ROOT, 'build', 'uniarc'),
                        help='uniarc binary (default: build/uniarc of this repository)')
    parser.add_argument('--sizes', type=int, nargs='+', default=[1000, 10000],
                        help='numbers of elements (default 1000 10000); n >= 1e5 needs --with-1e5')
    parser.add_argument('--with-1e5', action='store_true',
                        help='also run n = 100000 (and allow sizes of 1e5 and more)')
    parser.add_argument('--models', nargs='+', choices=['ring', 'beam'], default=['ring', 'beam'])
    parser.add_argument('--foundations', nargs='+', choices=['tensionless', 'bonded'],
                        default=['tensionless', 'bonded'])
    parser.add_argument('--programs', nargs='+', choices=['uniarc', 'opensees'], default=['uniarc', 'opensees'])
    parser.add_argument('--os-systems', nargs='+', default=['BandGeneral'],
                        help='OpenSees linear-system solvers, one set of OpenSees runs each '
                             '(default BandGeneral, the fastest measured; e.g. UmfPack SparseGeneral)')
    parser.add_argument('--os-test', choices=opensees_models.TESTS, default=opensees_models.TESTS[0],
                        help='OpenSees convergence test, tolerance 1e-8 (default RelativeNormDispIncr; '
                             'see bench/opensees_models.py)')
    parser.add_argument('--timeout', type=float, default=600.0, help='time limit of one run, s (default 600)')
    parser.add_argument('--repeat', type=int, default=1,
                        help='report the fastest of this many runs of each case (default 1)')
    parser.add_argument('--python', default=sys.executable, help='Python with openseespy (default: this one)')
    parser.add_argument('--workdir', help='keep the runs here (default: a temporary directory, removed)')
    parser.add_argument('--note', help='a line for the header of the table, e.g. which commit the binary is')
    parser.add_argument('-o', '--output', help='also write the Markdown to this file')
    args = parser.parse_args()

    sizes = list(args.sizes)
    if args.with_1e5 and LARGE not in sizes:
        sizes.append(LARGE)
    too_large = [n for n in sizes if n >= LARGE and not args.with_1e5]
    if too_large:
        parser.error('sizes of 1e5 and more need --with-1e5: %s' % too_large)
    for n in sizes:
        if 'beam' in args.models and n % int(opensees_models.BEAM['m']) != 0:
            parser.error('the beam needs n a multiple of %d, found %d' % (opensees_models.BEAM['m'], n))
        if 'ring' in args.models and n % 2 != 0:
            parser.error('the ring needs an even n, found %d' % n)
    binary = os.path.abspath(args.uniarc)
    if 'uniarc' in args.programs and not os.access(binary, os.X_OK):
        parser.error('no uniarc binary at %s (build it, or give --uniarc PATH)' % binary)
    if shutil.which('timeout') is None:
        parser.error('the timeout command (coreutils) is missing')

    workdir = args.workdir or tempfile.mkdtemp(prefix='contact_scale_')
    os.makedirs(workdir, exist_ok=True)

    baseline = None
    opensees_version = '—'
    if 'opensees' in args.programs:
        rc, wall, rss, out, err = timed_run(
            [args.python, '-c', 'import openseespy.opensees as o; print("version", o.version())'],
            args.timeout, workdir, 'opensees_import')
        if rc != 0:
            parser.error('openseespy does not import with %s (pip install openseespy): %s'
                         % (args.python, err.strip().splitlines()[-1:] or ''))
        baseline = (os.path.basename(args.python), wall, (rss or 0) / 1024.0)
        m = re.search(r'version (\S+)', out + err)
        opensees_version = m.group(1) if m else '?'

    uniarc_version = '—'
    if 'uniarc' in args.programs:
        uniarc_version = subprocess.run([binary, '--version'], capture_output=True, text=True).stdout.strip()
    cpu = '?'
    try:
        with open('/proc/cpuinfo') as f:
            cpu = next(line.split(':', 1)[1].strip() for line in f if line.startswith('model name'))
    except (OSError, StopIteration):
        pass
    header = [
        '## Contact at pipeline scale: uniarc and OpenSees, %s' % datetime.date.today().isoformat(),
        '',
        '`%s`' % shlex.join(['python3', os.path.relpath(__file__, ROOT)] + sys.argv[1:]),
        '',
        '- uniarc: `%s` (%s, built %s)' % (
            binary, uniarc_version,
            datetime.datetime.fromtimestamp(os.path.getmtime(binary)).strftime('%Y-%m-%d %H:%M'))
        if 'uniarc' in args.programs else '- uniarc: not run',
        '- OpenSees: openseespy %s, Python %s, test %s 1e-8' % (
            opensees_version, platform.python_version(), args.os_test)
        if 'opensees' in args.programs else '- OpenSees: not run',
        '- machine: %s, %d cores, load average %.2f at the start; time limit %g s per run; '
        'fastest of %d run(s) per case' % (cpu, os.cpu_count() or 0, os.getloadavg()[0], args.timeout,
                                           args.repeat),
    ]
    machine_line = len(header) - 1
    if args.note:
        header.append('- note: %s' % args.note)

    results = []
    for model in args.models:
        for n in sizes:
            for foundation in args.foundations:
                bonded = foundation == 'bonded'
                runs = []
                if 'uniarc' in args.programs:
                    runs.append(lambda: run_uniarc(binary, model, n, bonded, args.timeout, workdir))
                if 'opensees' in args.programs:
                    for system in args.os_systems:
                        runs.append(lambda system=system: run_opensees(model, n, bonded, system, args.timeout,
                                                                       workdir, args.python, args.os_test))
                for run in runs:
                    # The fastest of --repeat runs (the machine may be shared); a run that did not
                    # finish is not repeated.
                    r = run()
                    for _ in range(args.repeat - 1):
                        if r['status'] != 'ok':
                            break
                        again = run()
                        if again['status'] == 'ok' and again['wall'] < r['wall']:
                            r = again
                    results.append(r)
                    print('%-22s %-5s n=%-7d %-11s %-18s %8.2f s  %s' % (
                        r['program'], model, n, foundation, r['status'], r['wall'],
                        '' if r['rss_kb'] is None else '%.0f MB' % (r['rss_kb'] / 1024.0)),
                        file=sys.stderr, flush=True)

    header[machine_line] += '; load average %.2f at the end' % os.getloadavg()[0]
    text = markdown(results, baseline, header)
    sys.stdout.write(text)
    if args.output:
        os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
        with open(args.output, 'w') as f:
            f.write(text)
    if args.workdir is None:
        shutil.rmtree(workdir, ignore_errors=True)
    else:
        print('runs kept in %s' % workdir, file=sys.stderr)


if __name__ == '__main__':
    main()
