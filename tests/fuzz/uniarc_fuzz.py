#!/usr/bin/env python3
"""Seeded mutation fuzzer of uniarc's input decks, and the exit-code contract it checks.

Each mutant is a deck of the corpus (input/*.inp, tests/regression/decks/*.inp, tests/bad_decks/*.inp,
tests/fuzz/decks/*.inp) changed by one to three mutations: byte flips and odd bytes, token deletion and
duplication, a number replaced by an extreme (0, -1, 1e308, nan, an overflowing expression, a count
capped so that the model stays small), card and line shuffles, deletions and duplicates, truncation,
long tokens and deep parentheses. uniarc runs on it with a timeout and a memory limit, and the run must
keep the contract of docs/contracts.md:

- it ends by itself (no timeout) with exit code 0, 1 or 2: no signal, no Fortran runtime error,
  no sanitizer report;
- exit 2: a message `error: DECK:LINE:COL: ...` (or `error: DECK: ...` for the whole-deck checks) and
  nothing in the output directory;
- exit 0: the path, crit and shape files, every row complete, every number finite (NaN, Inf or a
  field of asterisks in any result file, VTK included, is a failure);
- exit 1: a message `error: ...`; the result files either all there with complete rows of finite
  numbers (the steps so far) or none (an I/O error);
- no lock or work directory left behind.

Mutant INDEX of seed SEED is a function of (SEED, INDEX) and the corpus only, so any failure is
reproduced with `--seed SEED --only INDEX --keep DIR`. Standard library only.

    uniarc_fuzz.py --uniarc build/uniarc --seed 1 --count 300 --jobs 2 --timeout 20
    uniarc_fuzz.py --uniarc build/uniarc --check input/walker_arch.inp --expect-exit 0

Exit status: 0 if every run kept the contract, 1 if any did not, 2 on a usage error.
"""

import argparse
import collections
import concurrent.futures
import json
import math
import os
import random
import re
import resource
import shutil
import signal
import subprocess
import sys
import time

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..'))
DEFAULT_CORPUS = ['input', 'tests/regression/decks', 'tests/bad_decks', 'tests/fuzz/decks']

# ---------------------------------------------------------------------------------------------------
# Mutations. Each takes the deck (bytes) and a random.Random and returns the mutated deck.

TOKEN = re.compile(rb'[A-Za-z_][A-Za-z0-9_]*|(?:\d+\.?\d*|\.\d+)(?:[eEdD][+-]?\d+)?|\*\*|\s+|.', re.S)
NUMBER = re.compile(rb'(?<![A-Za-z_0-9.])(?:\d+\.?\d*|\.\d+)(?:[eEdD][+-]?\d+)?')

# Extremes for a number. Counts stay below COUNT_CAP so that a mutated model stays small (an element
# count of 1e9 is a resource limit, tested elsewhere, not a deck the fuzzer should make); integers past
# the integer range and reals past the real range must be refused.
EXTREMES = [b'0', b'-0', b'-1', b'1', b'2', b'0.5', b'-0.5', b'3', b'7', b'1e308', b'-1e308', b'1e309',
            b'1e-308', b'4.9e-324', b'1e-300', b'nan', b'NaN', b'inf', b'-inf', b'2147483647', b'2147483648',
            b'-2147483649', b'9223372036854775808', b'1e19', b'1e10', b'1e-10', b'1e20', b'1.0000000000000002',
            b'(1/0)', b'(0/0)', b'sqrt(-1)', b'log(0)', b'2**1024', b'1e200*1e200', b'(-8)**(1/3)', b'0**-1',
            b'exp(710)', b'tand(90)', b'acos(2)', b'1d308', b'1.5D+400', b'.e1', b'1e', b'1.2.3', b'--1', b'+-1',
            b'1e306', b'1e300', b'1e200', b'1e150', b'1e100', b'1e-100', b'1e-150', b'1e-200', b'1e-306']
COUNT_CAP = 1000
ODD_BYTES = [b'\x00', b'\t', b'\r', b'\n', b',', b'*', b'=', b'(', b')', b'-', b'.', b'e', b'9', b'"', b"'",
             b'\xff', b'\xc3', b'\x1b', b' ', b'**', b'\r\n', b'!', b';', b'\\']


def flip_byte(deck, rng):
    if not deck:
        return b'\x00'
    i = rng.randrange(len(deck))
    return deck[:i] + bytes([deck[i] ^ (1 << rng.randrange(8))]) + deck[i + 1:]


def odd_byte(deck, rng):
    i = rng.randrange(len(deck) + 1)
    replace = rng.random() < 0.5 and i < len(deck)
    return deck[:i] + rng.choice(ODD_BYTES) + deck[i + (1 if replace else 0):]


def tokens(deck):
    return TOKEN.findall(deck)


def delete_token(deck, rng):
    parts = tokens(deck)
    if not parts:
        return deck
    del parts[rng.randrange(len(parts))]
    return b''.join(parts)


def duplicate_token(deck, rng):
    parts = tokens(deck)
    if not parts:
        return deck
    i = rng.randrange(len(parts))
    parts.insert(i, parts[i])
    return b''.join(parts)


def replace_number(deck, rng):
    matches = list(NUMBER.finditer(deck))
    if not matches:
        return odd_byte(deck, rng)
    m = rng.choice(matches)
    roll = rng.random()
    if roll < 0.6:
        value = rng.choice(EXTREMES)
    elif roll < 0.8:
        # A count: a whole number up to COUNT_CAP.
        value = str(rng.choice([0, 1, 2, 3, 5, 10, 100, rng.randrange(COUNT_CAP + 1)])).encode()
    else:
        # The number scaled: a change of size or sign that keeps the deck otherwise sensible.
        try:
            x = float(m.group().replace(b'd', b'e').replace(b'D', b'e'))
        except ValueError:
            x = 1.0
        factor = rng.choice([-1.0, 1e-300, 1e-100, 1e-8, 1e-3, 0.1, 0.999999, 1.000001, 10.0, 1e3, 1e8, 1e100, 1e300])
        y = x*factor
        value = repr(y).encode() if abs(y) < COUNT_CAP or not float(y).is_integer() else str(COUNT_CAP).encode()
    return deck[:m.start()] + value + deck[m.end():]


def split_cards(deck):
    """The deck as [prelude, card, card, ...], each card its keyword line and the lines up to the next."""
    lines = deck.splitlines(keepends=True)
    cards = [[]]
    for line in lines:
        stripped = line.lstrip()
        if stripped.startswith(b'*') and not stripped.startswith(b'**'):
            cards.append([])
        cards[-1].append(line)
    return [b''.join(card) for card in cards]


def ensure_newline(text):
    return text if text.endswith(b'\n') or not text else text + b'\n'


def shuffle_cards(deck, rng):
    cards = split_cards(deck)
    body = [ensure_newline(card) for card in cards[1:]]
    if len(body) < 2:
        return deck
    kind = rng.randrange(4)
    if kind == 0:
        rng.shuffle(body)
    elif kind == 1:
        i, j = rng.sample(range(len(body)), 2)
        body[i], body[j] = body[j], body[i]
    elif kind == 2:
        del body[rng.randrange(len(body))]
    else:
        i = rng.randrange(len(body))
        body.insert(rng.randrange(len(body) + 1), body[i])
    return cards[0] + b''.join(body)


def shuffle_lines(deck, rng):
    lines = [ensure_newline(line) for line in deck.splitlines(keepends=True)]
    if len(lines) < 2:
        return deck
    kind = rng.randrange(3)
    i = rng.randrange(len(lines))
    if kind == 0:
        del lines[i]
    elif kind == 1:
        lines.insert(rng.randrange(len(lines) + 1), lines[i])
    else:
        j = rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
    return b''.join(lines)


def truncate(deck, rng):
    return deck[:rng.randrange(len(deck) + 1)]


def long_token(deck, rng):
    """A long name, number, blank run or line, or deeply nested parentheses, at a random place."""
    size = rng.choice([100, 1000, 10000, 100000])
    kind = rng.randrange(6)
    if kind == 0:
        token = b'a'*size
    elif kind == 1:
        token = b'9'*size
    elif kind == 2:
        token = b' '*size
    elif kind == 3:
        token = b'1' + b'+1'*(size//2)
    elif kind == 4:
        depth = rng.choice([10, 100, 1000, 10000, 50000])
        token = b'('*depth + b'1' + b')'*depth
    else:
        token = b'-'*size + b'1'
    i = rng.randrange(len(deck) + 1)
    if rng.random() < 0.5:
        matches = list(NUMBER.finditer(deck))
        if matches:
            m = rng.choice(matches)
            return deck[:m.start()] + token + deck[m.end():]
    return deck[:i] + token + deck[i:]


def change_case(deck, rng):
    parts = tokens(deck)
    words = [k for k, p in enumerate(parts) if p[:1].isalpha()]
    if not words:
        return deck
    k = rng.choice(words)
    parts[k] = rng.choice([parts[k].lower(), parts[k].upper(), parts[k].swapcase()])
    return b''.join(parts)


MUTATIONS = {
    'flip_byte': flip_byte, 'odd_byte': odd_byte, 'delete_token': delete_token,
    'duplicate_token': duplicate_token, 'replace_number': replace_number, 'shuffle_cards': shuffle_cards,
    'shuffle_lines': shuffle_lines, 'truncate': truncate, 'long_token': long_token, 'change_case': change_case,
}
# replace_number is drawn most often: most decks that parse make the analysis do something new.
WEIGHTS = {'flip_byte': 2, 'odd_byte': 1, 'delete_token': 2, 'duplicate_token': 1, 'replace_number': 6,
           'shuffle_cards': 2, 'shuffle_lines': 1, 'truncate': 1, 'long_token': 1, 'change_case': 1}


def mutant(corpus, seed, index):
    """Mutant `index` of `seed`: (base deck path, list of mutation names, deck bytes)."""
    rng = random.Random(f'uniarc-fuzz:{seed}:{index}')
    # Decks that run are drawn four times as often as the refused ones of tests/bad_decks: most of
    # their mutants still parse and reach the analysis.
    weights = [1 if os.sep + 'bad_decks' + os.sep in deck else 4 for deck in corpus]
    base = rng.choices(corpus, weights=weights)[0]
    with open(base, 'rb') as f:
        deck = f.read()
    names = rng.choices(list(WEIGHTS), weights=list(WEIGHTS.values()), k=rng.choice([1, 1, 1, 2, 2, 3]))
    for name in names:
        deck = MUTATIONS[name](deck, rng)
    return base, names, deck


# ---------------------------------------------------------------------------------------------------
# The contract.

CRASH_MARKERS = ['Fortran runtime error', 'Program received signal', 'Backtrace for this error',
                 'Error termination', 'ERROR STOP', 'AddressSanitizer', 'LeakSanitizer',
                 'UndefinedBehaviorSanitizer', 'runtime error:', 'Operating system error']
TABLES = ('.path', '.crit', '.shape', '.surface', '.forces', '.contact', '.csv')
REQUIRED_TABLES = ('.path', '.crit', '.shape')


def finite_token(token):
    try:
        return math.isfinite(float(token))
    except ValueError:
        return False


def check_table(path, problems):
    """Every row of a result table has the header's number of fields, and its numbers are finite."""
    with open(path, 'rb') as f:
        text = f.read().decode('utf-8', 'replace')
    if text and not text.endswith('\n'):
        problems.append(('torn_row', f'{os.path.basename(path)}: last line not ended'))
    lines = text.splitlines()
    # The column names are line 1 (no '#'); '#' lines are provenance (docs/contracts.md).
    if not lines or not lines[0].strip() or lines[0].startswith('#'):
        problems.append(('torn_row', f'{os.path.basename(path)}: no header line'))
        return
    header = lines[0].replace(',', ' ').split()
    # Columns of words: the event kind and the analysis step's name of .crit, the medium's name of .contact and .surface.
    word_columns = {k for k, name in enumerate(header) if name in ('kind', 'medium', 'step_name')}
    for number, line in enumerate(lines[1:], start=2):
        if not line.strip() or line.startswith('#'):
            continue
        fields = line.replace(',', ' ').split()
        if len(fields) != len(header):
            problems.append(('torn_row', f'{os.path.basename(path)}:{number}: {len(fields)} fields, header has {len(header)}'))
            return
        for k, field in enumerate(fields):
            if k in word_columns and re.fullmatch(r'[A-Za-z_][A-Za-z0-9_.-]*', field):
                continue
            if not finite_token(field):
                kind = 'nonfinite' if re.search(r'(?i)nan|inf|\*', field) else 'torn_row'
                problems.append((kind, f'{os.path.basename(path)}:{number}: field {k + 1} is {field[:30]!r}'))
                return


VTK_NUMBER_LIKE = re.compile(r'(?i)(?<![A-Za-z_])[-+]?(nan|inf(inity)?)(?![A-Za-z_])|\*{2,}')


def check_other_file(path, problems):
    """NaN, Inf or asterisks among the numbers of a ParaView file (the legacy title line skipped)."""
    with open(path, 'rb') as f:
        text = f.read().decode('utf-8', 'replace')
    if path.endswith('.vtp'):
        text = '\n'.join(re.findall(r'<DataArray[^>]*>(.*?)</DataArray>', text, re.S))
    elif path.endswith('.vtk'):
        text = '\n'.join(text.splitlines()[2:])
    else:
        return
    m = VTK_NUMBER_LIKE.search(text)
    if m:
        problems.append(('nonfinite', f'{os.path.basename(path)}: {m.group()!r}'))


def judge(deck_name, returncode, timed_out, stderr, outdir, read_files=()):
    """The contract's verdict on one run: ('exit0'|'exit1'|'exit2', []) or (outcome, [(class, detail)]).
    read_files: the paths of the other files the deck reads (a modes table of *IMPERFECTION, FILE=), as
    the deck writes them: an exit 2 may name one of them, at the line and column of its fault."""
    problems = []
    if timed_out:
        return 'timeout', [('timeout', 'no exit within the time limit')]
    if returncode < 0:
        name = signal.Signals(-returncode).name if -returncode in signal.Signals._value2member_map_ else str(-returncode)
        detail = first_line(stderr, CRASH_MARKERS) or '(no message)'
        frame = re.search(r'__(\w+)_MOD_(\w+)', stderr)    # the innermost procedure of a gfortran backtrace
        if frame:
            detail += f' in {frame.group(1)}::{frame.group(2)}'
        return 'signal', [(f'signal {name}', detail)]
    marker = next((m for m in CRASH_MARKERS if m in stderr), None)
    if marker:
        detail = first_line(stderr, [marker])
        at = re.search(r'At line (\d+) of file (\S+)', stderr)
        if at:
            detail += f' at {os.path.basename(at.group(2))}:{at.group(1)}'
        problems.append(('runtime error', detail))
    if returncode not in (0, 1, 2):
        problems.append((f'exit code {returncode}', first_line(stderr, ['error']) or '(no message)'))
        return f'exit{returncode}', problems
    files = []
    if os.path.isdir(outdir):
        for root, dirs, names in os.walk(outdir):
            files += [os.path.join(root, n) for n in names]
            files += [os.path.join(root, d) + '/' for d in dirs]
    leftovers = [f for f in files if f.endswith('.lock') or '.part' in os.path.basename(f.rstrip('/'))]
    if leftovers:
        problems.append(('lock or work directory left', ', '.join(os.path.basename(f.rstrip('/')) for f in leftovers[:3])))
    if returncode == 2:
        names = '|'.join(re.escape(n) for n in (deck_name, *read_files))
        location = re.compile(r'^error: (?:' + names + r'):(\d+:\d+:)? \S', re.M)
        if not location.search(stderr):
            problems.append(('exit 2 without file:line:col', first_line(stderr, ['error']) or '(no message)'))
        if files:
            problems.append(('exit 2 with output', ', '.join(os.path.basename(f) for f in files[:3])))
        return 'exit2', problems
    if returncode == 1 and not re.search(r'^error: \S', stderr, re.M):
        problems.append(('exit 1 without a message', first_line(stderr, ['']) or '(empty stderr)'))
    results = [f for f in files if not f.endswith('/') and f not in leftovers]
    tables = {ext: [f for f in results if f.endswith(ext)] for ext in TABLES}
    if returncode == 0 or results:
        for ext in REQUIRED_TABLES:
            if not tables[ext]:
                problems.append(('result file missing', f'no {ext} (exit {returncode})'))
    for f in results:
        if f.endswith(TABLES):
            check_table(f, problems)
        else:
            check_other_file(f, problems)
    problems = [(f'{kind} (exit {returncode})' if kind in ('nonfinite', 'torn_row') else kind, detail)
                for kind, detail in problems]
    return f'exit{returncode}', problems


def deck_features(deck):
    """What makes a deck extreme, for the report of a crash or a timeout: nesting and line length."""
    depth = deepest = run = longest_run = 0
    for byte in deck:
        if byte == 40:            # (
            depth += 1
            deepest = max(deepest, depth)
        elif byte == 41:          # )
            depth = max(depth - 1, 0)
        if byte in (43, 45):      # + -
            run += 1
            longest_run = max(longest_run, run)
        elif byte not in (32, 9):
            run = 0
    longest_line = max((len(line) for line in deck.split(b'\n')), default=0)
    return f'deck: nesting {max(deepest, longest_run)}, longest line {longest_line}'


def first_line(text, markers):
    for line in text.splitlines():
        if any(m in line for m in markers):
            return line.strip()[:200]
    return ''


def limit_resources(memory_mb, file_mb):
    def apply():
        os.setsid()
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        # AddressSanitizer reserves terabytes of address space for its shadow memory: no limit under it.
        if memory_mb and 'ASAN_OPTIONS' not in os.environ:
            resource.setrlimit(resource.RLIMIT_AS, (memory_mb << 20, memory_mb << 20))
        if file_mb:
            resource.setrlimit(resource.RLIMIT_FSIZE, (file_mb << 20, file_mb << 20))
    return apply


def read_files(deck_path):
    """The files a deck reads besides itself, as uniarc names them in a message: each FILE= of the deck
    (a relative path is the deck's folder's, which uniarc prefixes as the folder of the deck's path)."""
    try:
        text = open(deck_path, errors='replace').read()
    except OSError:
        return ()
    return tuple(m.group(1) for m in re.finditer(r'(?im)^\*IMPERFECTION\b[^\n]*\bFILE\s*=\s*([^,\s]+)', text))


def run_deck(uniarc, deck_path, workdir, timeout, memory_mb, file_mb, defines=()):
    """Run uniarc on the deck (copied into workdir) and judge the run. Returns a result dict."""
    os.makedirs(workdir, exist_ok=True)
    name = os.path.basename(deck_path)
    outdir = os.path.join(workdir, 'out')
    command = [uniarc, name, '-o', 'out', '-q']
    for define in defines:
        command += ['-D', define]
    start = time.monotonic()
    timed_out = False
    process = subprocess.Popen(command, cwd=workdir, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               preexec_fn=limit_resources(memory_mb, file_mb))
    try:
        _, stderr = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        timed_out = True
        os.killpg(process.pid, signal.SIGKILL)
        _, stderr = process.communicate()
    seconds = time.monotonic() - start
    stderr = stderr.decode('utf-8', 'replace')
    outcome, problems = judge(name, process.returncode, timed_out, stderr, outdir, read_files(deck_path))
    return {'outcome': outcome, 'problems': problems, 'seconds': seconds, 'command': command,
            'returncode': process.returncode, 'stderr_head': stderr[:2000]}


# ---------------------------------------------------------------------------------------------------

def load_corpus(entries):
    decks = []
    for entry in entries:
        path = entry if os.path.isabs(entry) else os.path.join(REPO, entry)
        if os.path.isdir(path):
            decks += sorted(os.path.join(path, n) for n in os.listdir(path) if n.endswith('.inp'))
        elif os.path.isfile(path):
            decks.append(path)
    # A deck whose comment says `** fuzz: skip` (with its reason) is not a seed: decks built to overflow
    # (the Release-only non-finite tests, which the Debug build's FPE traps stop by design) or to run
    # long (the interrupt and memory-limit tests).
    return [d for d in decks if not re.search(rb'^\*\* fuzz: skip', open(d, 'rb').read(), re.M)]


def fuzz_one(args, corpus, index):
    base, names, deck = mutant(corpus, args.seed, index)
    workdir = os.path.join(args.work, f'm{index:06d}')
    shutil.rmtree(workdir, ignore_errors=True)
    os.makedirs(workdir)
    deck_path = os.path.join(workdir, os.path.basename(base))
    with open(deck_path, 'wb') as f:
        f.write(deck)
    result = run_deck(args.uniarc, deck_path, workdir, args.timeout, args.memory_mb, args.file_mb)
    if result['outcome'] in ('signal', 'timeout'):
        result['problems'] = [(kind, f'{detail} [{deck_features(deck)}]') for kind, detail in result['problems']]
    result.update(index=index, base=os.path.relpath(base, REPO), mutations=names, size=len(deck))
    result['known'] = [p for p in result['problems'] if any(k.search(f'{p[0]} | {p[1]}') for k in args.known_patterns)]
    result['problems'] = [p for p in result['problems'] if p not in result['known']]
    if (result['problems'] or result['known']) and args.keep:
        keep = os.path.join(args.keep, f'seed{args.seed}_m{index:06d}')
        shutil.rmtree(keep, ignore_errors=True)
        os.makedirs(keep)
        shutil.copy(deck_path, keep)
        with open(os.path.join(keep, 'failure.txt'), 'w') as f:
            f.write(f'seed {args.seed} mutant {index} of {result["base"]} by {", ".join(names)}\n')
            f.write(f'command (in this directory): {" ".join(result["command"])}\n')
            f.write(f'exit {result["returncode"]} after {result["seconds"]:.1f} s\n')
            for kind, detail in result['problems'] + result['known']:
                f.write(f'{kind}: {detail}\n')
            f.write('--- stderr (head) ---\n' + result['stderr_head'])
    shutil.rmtree(workdir, ignore_errors=True)
    return result


def summarise(args, results, elapsed):
    outcomes = collections.Counter(r['outcome'] for r in results)
    classes = collections.Counter()
    known = collections.Counter()
    examples = {}
    for r in results:
        for kind, detail in r['problems'] + r['known']:
            # One class per kind and message shape: digits and quoted text do not make a new class.
            key = kind + ' | ' + re.sub(r"'[^']*'|\d+(\.\d+)?([eE][-+]?\d+)?", '#', detail)[:120]
            (known if (kind, detail) in r['known'] else classes)[key] += 1
            examples.setdefault(key, (r['index'], r['base'], r['mutations'], detail))
    failed = sum(1 for r in results if r['problems'])
    slowest = max(results, key=lambda r: r['seconds']) if results else None
    summary = {
        'seed': args.seed, 'mutants': len(results), 'uniarc': args.uniarc, 'timeout_s': args.timeout,
        'memory_mb': args.memory_mb, 'jobs': args.jobs, 'elapsed_s': round(elapsed, 1),
        'outcomes': dict(sorted(outcomes.items())), 'failed_mutants': failed,
        'failure_classes': {k: {'count': v, 'example': {'index': examples[k][0], 'base': examples[k][1],
                                                         'mutations': examples[k][2], 'detail': examples[k][3]}}
                            for k, v in classes.most_common()},
        'known_classes': {k: {'count': v, 'example': {'index': examples[k][0], 'base': examples[k][1],
                                                       'mutations': examples[k][2], 'detail': examples[k][3]}}
                          for k, v in known.most_common()},
        'known_mutants': sum(1 for r in results if r['known'] and not r['problems']),
        'slowest': {'index': slowest['index'], 'base': slowest['base'], 'seconds': round(slowest['seconds'], 2)}
        if slowest else None,
    }
    lines = [f'uniarc fuzz: seed {args.seed}, {len(results)} mutants, {elapsed:.0f} s, {args.jobs} jobs, '
             f'timeout {args.timeout} s, {args.uniarc}']
    lines.append('outcomes: ' + ', '.join(f'{k} {v}' for k, v in sorted(outcomes.items())))
    lines.append(f'mutants that broke the contract: {failed}')
    for key, count in classes.most_common():
        index, base, names, detail = examples[key]
        lines.append(f'  {count:6d}  {key}')
        lines.append(f'          e.g. --seed {args.seed} --only {index}: {base} by {"+".join(names)}: {detail}')
    if known:
        lines.append(f'mutants with known, open failures only (--known): {summary["known_mutants"]}')
        for key, count in known.most_common():
            index, base, names, detail = examples[key]
            lines.append(f'  {count:6d}  known: {key}')
            lines.append(f'          e.g. --seed {args.seed} --only {index}: {base} by {"+".join(names)}: {detail}')
    if slowest:
        lines.append(f'slowest run: {slowest["seconds"]:.1f} s (mutant {slowest["index"]} of {slowest["base"]})')
    return summary, '\n'.join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--uniarc', required=True, help='the uniarc executable')
    parser.add_argument('--seed', type=int, default=None, help='seed (default: a random one, printed)')
    parser.add_argument('--count', type=int, default=100, help='number of mutants')
    parser.add_argument('--first', type=int, default=0, help='index of the first mutant')
    parser.add_argument('--only', type=int, action='append', help='run only mutant INDEX (repeatable)')
    parser.add_argument('--jobs', type=int, default=2)
    parser.add_argument('--timeout', type=float, default=20.0, help='seconds per run')
    parser.add_argument('--memory-mb', type=int, default=2048,
                        help='address-space limit per run (0: none; none either when ASAN_OPTIONS is set)')
    parser.add_argument('--file-mb', type=int, default=256, help='file-size limit per run (0: none)')
    parser.add_argument('--corpus', nargs='+', default=DEFAULT_CORPUS, help='decks or folders of decks')
    parser.add_argument('--work', default=None, help='scratch folder (default: a folder in /tmp)')
    parser.add_argument('--keep', default=None, help='copy each failing mutant and its report here')
    parser.add_argument('--summary', default=None, help='write the summary here (and SUMMARY.json)')
    parser.add_argument('--known', default=None,
                        help='file of regular expressions (one a line, # comments) matching "class | detail" '
                             'of failures that are known and open: reported, but the exit status ignores them')
    parser.add_argument('--check', nargs='+', default=None, help='run these decks unmutated and judge them')
    parser.add_argument('--define', '-D', action='append', default=[], help='with --check: -D NAME=VALUE')
    parser.add_argument('--expect-exit', type=int, choices=[0, 1, 2], default=None,
                        help='with --check: the exit code each deck must give')
    args = parser.parse_args()
    args.uniarc = os.path.abspath(args.uniarc)
    if not os.access(args.uniarc, os.X_OK):
        parser.error(f'{args.uniarc} is not an executable')
    args.known_patterns = []
    if args.known:
        with open(args.known) as f:
            for line in f:
                line = line.strip()
                if line and not line.startswith('#'):
                    args.known_patterns.append(re.compile(line))
    work_owned = args.work is None
    if work_owned:
        import tempfile
        args.work = tempfile.mkdtemp(prefix='uniarc_fuzz_')
    os.makedirs(args.work, exist_ok=True)

    if args.check:
        failed = 0
        for k, deck in enumerate(args.check):
            workdir = os.path.join(args.work, f'check{k}')
            shutil.rmtree(workdir, ignore_errors=True)
            os.makedirs(workdir)
            shutil.copy(deck, workdir)
            r = run_deck(args.uniarc, os.path.join(workdir, os.path.basename(deck)), workdir, args.timeout,
                         args.memory_mb, args.file_mb, args.define)
            problems = list(r['problems'])
            if args.expect_exit is not None and r['returncode'] != args.expect_exit:
                problems.append(('unexpected exit code', f'{r["returncode"]}, expected {args.expect_exit}'))
            status = 'FAIL' if problems else 'ok'
            print(f'{status}: {deck}: {r["outcome"]} in {r["seconds"]:.1f} s')
            for kind, detail in problems:
                print(f'  {kind}: {detail}')
            if problems:
                failed += 1
                print('--- stderr (head) ---\n' + r['stderr_head'])
        if work_owned:
            shutil.rmtree(args.work, ignore_errors=True)
        return 1 if failed else 0

    if args.seed is None:
        args.seed = random.SystemRandom().randrange(1 << 31)
    corpus = load_corpus(args.corpus)
    if not corpus:
        parser.error('no decks in the corpus')
    indices = args.only if args.only else range(args.first, args.first + args.count)
    print(f'uniarc fuzz: seed {args.seed}, {len(indices)} mutants of {len(corpus)} decks', flush=True)
    start = time.monotonic()
    results = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = [pool.submit(fuzz_one, args, corpus, i) for i in indices]
        for n, future in enumerate(concurrent.futures.as_completed(futures), start=1):
            r = future.result()
            results.append(r)
            for kind, detail in r['problems']:
                print(f'FAIL mutant {r["index"]} ({r["base"]} by {"+".join(r["mutations"])}): {kind}: {detail}',
                      flush=True)
            if n % 500 == 0:
                print(f'... {n} mutants, {sum(1 for x in results if x["problems"])} failed, '
                      f'{time.monotonic() - start:.0f} s', flush=True)
    results.sort(key=lambda r: r['index'])
    summary, text = summarise(args, results, time.monotonic() - start)
    print(text)
    if args.summary:
        with open(args.summary, 'w') as f:
            f.write(text + '\n')
        with open(args.summary + '.json', 'w') as f:
            json.dump(summary, f, indent=1)
    if work_owned:
        shutil.rmtree(args.work, ignore_errors=True)
    return 1 if summary['failed_mutants'] else 0


if __name__ == '__main__':
    sys.exit(main())
