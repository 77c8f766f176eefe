#!/usr/bin/env python3
"""The run loop's contract on interrupts, memory and non-finite results (docs/contracts.md,
"Interrupts", "Memory", "Non-finite results", "Checking a deck").

  run_loop_check.py --uniarc EXE --deck DECK --out DIR --signal TERM|INT
      Starts a long run, waits until its work directory holds at least 20 rows of STEM.path, sends
      the signal and expects: exit code 128 + the signal's number (143, 130), the message
      "interrupted by SIGxxx after step N", STEM.path/.crit/.shape under their final names with
      the complete rows of steps 0..N (N >= 20, consecutive, every row as many fields as the
      header), the last shape snapshot at step N, and neither STEM.lock nor a work directory left.

  run_loop_check.py --uniarc EXE --deck DECK --out DIR --memory-limit MB [--check]
      Runs under an address-space limit (RLIMIT_AS, `ulimit -v`) that the model's estimated memory
      exceeds: exit code 2, "does not fit in memory" with the estimate and the limit, no file and
      no stdout of an analysis. With --check, `uniarc --check` must refuse the same way after
      printing the summary. Without the limit, --check must pass (the model itself is valid).

  run_loop_check.py --uniarc EXE --deck DECK --out DIR --summary NAME=VALUE...
      `uniarc --check DECK`: exit code 0, each summary line NAME starts with VALUE, a memory
      estimate, and no file written (OUTDIR and the working directory untouched). Then `uniarc -v
      DECK`: exit code 0, and its first line on stderr is "memory: " with the same estimate.

  run_loop_check.py --uniarc EXE --deck DECK --out DIR --non-finite [--files]
      A run whose numbers overflow: exit code 1 and "not finite" in the message; with --files the
      result files of the steps before are written (row 0 at least), else none; no file holds a
      NaN or Inf.
"""
import argparse
import os
import re
import resource
import shutil
import signal
import subprocess
import sys
import time


def fresh(directory):
    shutil.rmtree(directory, ignore_errors=True)
    os.makedirs(directory)


def stem_of(deck):
    return os.path.splitext(os.path.basename(deck))[0]


def is_row(line):
    """A line of numbers (not the column names, a provenance comment or a blank line)."""
    fields = line.split()
    try:
        float(fields[0])
        return True
    except (IndexError, ValueError):
        return False


def leftovers(out, stem):
    return [name for name in os.listdir(out) if name == stem + '.lock' or name.startswith('.' + stem + '.part')]


def check_signal(args, failures):
    stem = stem_of(args.deck)
    number = {'TERM': signal.SIGTERM, 'INT': signal.SIGINT}[args.signal]
    fresh(args.out)
    process = subprocess.Popen([args.uniarc, args.deck, '-o', args.out, '-q'], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    work = os.path.join(args.out, f'.{stem}.part.{process.pid}', stem + '.path')
    deadline = time.monotonic() + 120
    rows = 0
    while time.monotonic() < deadline and process.poll() is None:
        if os.path.exists(work):
            with open(work) as handle:
                rows = sum(1 for line in handle if is_row(line))
            if rows >= 21:
                break
        time.sleep(0.05)
    if process.poll() is not None:
        failures.append(f'the run ended by itself (exit code {process.returncode}) before the signal')
        return
    process.send_signal(number)
    try:
        stdout, stderr = process.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        process.kill()
        failures.append('the run did not end within 120 s of the signal')
        return
    print(stderr, end='')
    expected_code = 128 + int(number)
    if process.returncode != expected_code:
        failures.append(f'exit code {process.returncode}, expected {expected_code}')
    match = re.search(rf'interrupted by SIG{args.signal} after step (\d+)', stderr)
    if not match:
        failures.append(f'stderr lacks "interrupted by SIG{args.signal} after step N"')
        return
    last = int(match.group(1))
    if leftovers(args.out, stem):
        failures.append(f'left behind: {leftovers(args.out, stem)}')
    for suffix in ('.path', '.crit', '.shape'):
        if not os.path.exists(os.path.join(args.out, stem + suffix)):
            failures.append(f'{stem}{suffix} is missing')
    if failures:
        return
    with open(os.path.join(args.out, stem + '.path')) as handle:
        lines = handle.read().splitlines()
    header = lines[0].lstrip('#').split()
    steps = []
    for line in lines[1:]:
        if line.startswith('#'):
            continue   # provenance lines under the column names
        fields = line.split()
        if len(fields) != len(header):
            failures.append(f'a torn row: {line!r}')
            return
        steps.append(float(fields[0]))
    if steps != [float(k) for k in range(last + 1)]:
        failures.append(f'the steps are not 0..{last}: {steps[:3]} ... {steps[-3:]}')
    if last < 20:
        failures.append(f'interrupted after step {last}, fewer than the 20 rows seen before the signal')
    with open(os.path.join(args.out, stem + '.shape')) as handle:
        shape_steps = [float(line.split()[0]) for line in handle if is_row(line)]
    if not shape_steps or shape_steps[-1] != float(last):
        failures.append(f'the last shape snapshot is not at step {last}')
    if not failures:
        print(f'ok: SIG{args.signal} after step {last}: exit code {process.returncode}, {last + 1} complete rows, '
              f'no lock or work directory left')


def run(args, extra, limit_bytes=None):
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (limit_bytes, limit_bytes))
    return subprocess.run([args.uniarc, *extra, args.deck, '-o', args.out], capture_output=True, text=True,
                          timeout=600, preexec_fn=limit if limit_bytes is not None else None)


def check_memory(args, failures):
    fresh(args.out)
    limit_bytes = args.memory_limit * 1000 * 1000
    extra = ['--check'] if args.check else ['-q']
    result = run(args, extra, limit_bytes)
    print(result.stdout + result.stderr, end='')
    if result.returncode != 2:
        failures.append(f'exit code {result.returncode}, expected 2')
    if 'does not fit in memory' not in result.stderr or 'ulimit -v' not in result.stderr:
        failures.append('the message lacks "does not fit in memory" and the limit it met (ulimit -v)')
    if not re.search(r'need about [0-9.]+ [kMGT]?B', result.stderr):
        failures.append('the message lacks the estimate ("need about N MB")')
    if os.listdir(args.out):
        failures.append(f'files written: {os.listdir(args.out)}')
    if args.check and 'memory' not in result.stdout:
        failures.append('--check printed no summary with the memory estimate before refusing')
    if not args.check and result.stdout:
        failures.append(f'an analysis started: {result.stdout!r}')
    unlimited = run(args, ['--check'])
    if unlimited.returncode != 0:
        failures.append(f'without the limit --check exits with {unlimited.returncode}: {unlimited.stderr}')


def check_summary(args, failures):
    fresh(args.out)
    before = sorted(os.listdir('.'))
    result = run(args, ['--check'])
    print(result.stdout + result.stderr, end='')
    if result.returncode != 0:
        failures.append(f'exit code {result.returncode}, expected 0')
    lines = {}
    for line in result.stdout.splitlines():
        if line.startswith('  ') and line[2:3] != ' ':
            lines[line[2:18].strip()] = line[18:]
    for expectation in args.summary:
        name, value = expectation.split('=', 1)
        if not lines.get(name, '').startswith(value):
            failures.append(f'summary line {name!r} is {lines.get(name)!r}, expected it to start with {value!r}')
    if not re.match(r'about [0-9.]+ [kMGT]?B estimated', lines.get('memory', '')):
        failures.append('no memory estimate in the summary')
    if os.listdir(args.out) or sorted(os.listdir('.')) != before:
        failures.append('--check wrote a file')
    # -v: the same estimate on stderr before the analysis, with what is available (Progress and messages).
    verbose = run(args, ['-v'])
    if verbose.returncode != 0:
        failures.append(f'uniarc -v exits with {verbose.returncode}: {verbose.stderr[-500:]}')
    estimate = re.match(r'about [0-9.]+ [kMGT]?B estimated', lines.get('memory', ''))
    first = verbose.stderr.splitlines()[0] if verbose.stderr else ''
    print(first)
    if not estimate or not re.match(r'memory: ' + re.escape(estimate.group(0)) + r'(; [0-9.]+ [kMGT]?B available \(.+\))?$',
                                    first):
        failures.append(f'the first line of uniarc -v on stderr is {first!r}, expected "memory: " and the estimate '
                        f'of --check ({lines.get("memory")!r})')


def check_non_finite(args, failures):
    fresh(args.out)
    result = run(args, ['-q'])
    print(result.stderr, end='')
    if result.returncode != 1:
        failures.append(f'exit code {result.returncode}, expected 1')
    if 'not finite' not in result.stderr:
        failures.append('the message lacks "not finite"')
    names = os.listdir(args.out)
    # A work directory left behind (a run killed by a sanitizer) is a failure, not a file to read.
    folders = [name for name in names if os.path.isdir(os.path.join(args.out, name))]
    if folders:
        failures.append(f'folders left behind: {folders}')
        names = [name for name in names if name not in folders]
    if args.files and stem_of(args.deck) + '.path' not in names:
        failures.append(f'the files of the steps before are missing: {names}')
    if not args.files and names:
        failures.append(f'files written: {names}')
    for name in names:
        with open(os.path.join(args.out, name)) as handle:
            numbers = [field.lower() for line in handle if not line.startswith('#') for field in line.split()]
        if any('nan' in field or 'inf' in field for field in numbers):
            failures.append(f'{name} holds a NaN or Inf')


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--uniarc', required=True)
    parser.add_argument('--deck', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--signal', choices=['TERM', 'INT'])
    parser.add_argument('--memory-limit', type=int, help='address-space limit in MB')
    parser.add_argument('--check', action='store_true')
    parser.add_argument('--summary', nargs='+')
    parser.add_argument('--non-finite', action='store_true')
    parser.add_argument('--files', action='store_true')
    args = parser.parse_args()
    failures = []
    if args.signal:
        check_signal(args, failures)
    elif args.memory_limit:
        check_memory(args, failures)
    elif args.summary:
        check_summary(args, failures)
    elif args.non_finite:
        check_non_finite(args, failures)
    else:
        parser.error('one of --signal, --memory-limit, --summary, --non-finite')
    for failure in failures:
        print('FAIL:', failure)
    sys.exit(1 if failures else 0)


if __name__ == '__main__':
    main()
