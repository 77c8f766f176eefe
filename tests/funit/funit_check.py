#!/usr/bin/env python3
"""Checks of uniarc's pFUnit fallback that a passing test cannot make (run by ctest).

    funit_check.py failures EXECUTABLE SUITE.pf...
        Runs a test executable built from the given suites, some of them deliberately failing, and
        checks that
          - it exits non-zero;
          - every line marked "! expect failure: TEXT" in a suite is reported as
            "SUITE.pf:LINE: ..." with TEXT in the report, and no other line is reported;
          - nothing printed "UNREACHED" (the first failing assertion ends its procedure, a failed
            @before skips its test and @after);
          - the closing line counts every test: passed, failed (one per marker), skipped (@disable);
          - the @after fixtures that print "after-fixture ran" ran once per test that ran.

    funit_check.py rejected PYTHON TRANSLATOR BAD.pf
        Runs the translator on BAD.pf, which has one line marked "! expect rejection: TEXT", and
        checks that it exits non-zero with "BAD.pf:LINE: TEXT" on stderr.

Exit status 0 when every check holds; otherwise the failed checks are printed and the status is 1.
"""

import os
import re
import subprocess
import sys
import tempfile


def marked_lines(path, marker):
    """(line number, text) of each line of ``path`` carrying ``! <marker>: text``."""
    found = []
    with open(path, encoding='utf-8') as handle:
        for number, line in enumerate(handle, start=1):
            match = re.search(r'!\s*' + marker + r':\s*(.*?)\s*$', line)
            if match:
                found.append((number, match.group(1)))
    return found


def count_tests(path):
    """(tests, disabled tests) declared in a .pf file."""
    with open(path, encoding='utf-8') as handle:
        text = handle.read()
    tests = len(re.findall(r'^\s*@test\s*$', text, re.MULTILINE | re.IGNORECASE))
    disabled = len(re.findall(r'^\s*@disable\s*$', text, re.MULTILINE | re.IGNORECASE))
    return tests, disabled


def failure_blocks(output):
    """Map each reported 'file.pf:LINE' to the text of its report (up to the next test line)."""
    blocks, current = {}, None
    for line in output.splitlines():
        match = re.match(r'\s*(\S+\.pf:\d+): ', line)
        if match:
            current = match.group(1)
            blocks[current] = line
        elif re.match(r'\s{2}(pass|FAIL|disabled)\s', line) or re.match(r'\d+ passed', line):
            current = None
        elif current:
            blocks[current] += '\n' + line
    return blocks


def check_failures(executable, suites):
    problems = []
    run = subprocess.run([executable], capture_output=True, text=True, timeout=120)
    output = run.stdout + run.stderr
    print(output)
    if run.returncode == 0:
        problems.append('the executable exited with status 0 although tests failed')

    blocks = failure_blocks(run.stdout)
    wanted = set()
    tests, disabled, after_expected = 0, 0, 0
    for suite in suites:
        name = os.path.basename(suite)
        for line, text in marked_lines(suite, 'expect failure'):
            wanted.add(f'{name}:{line}')
            block = blocks.get(f'{name}:{line}')
            if block is None:
                problems.append(f'no failure reported at {name}:{line}')
            elif text not in block:
                problems.append(f'the failure at {name}:{line} does not say "{text}":\n{block}')
        suite_tests, suite_disabled = count_tests(suite)
        tests, disabled = tests + suite_tests, disabled + suite_disabled
        with open(suite, encoding='utf-8') as handle:
            if "'after-fixture ran'" in handle.read():
                after_expected += suite_tests - suite_disabled
    for location in blocks:
        if location not in wanted:
            problems.append(f'unexpected failure at {location} (an assertion after a failed one '
                            'ran, or a passing suite failed)')
    if 'UNREACHED' in output:
        problems.append('a statement that must not run ran')

    summary = f'{tests - disabled - len(wanted)} passed, {len(wanted)} failed, {disabled} skipped'
    if summary not in run.stdout.splitlines():
        problems.append(f'the summary line "{summary}" is missing')
    after_runs = run.stdout.count('after-fixture ran')
    if after_runs != after_expected:
        problems.append(f'@after ran {after_runs} times for {after_expected} tests that ran')
    return problems


def check_rejected(python, translator, source):
    problems = []
    marks = marked_lines(source, 'expect rejection')
    if len(marks) != 1:
        return [f'{source} must have exactly one "! expect rejection:" line']
    line, text = marks[0]
    with tempfile.TemporaryDirectory() as scratch:
        output = os.path.join(scratch, 'out.f90')
        run = subprocess.run([python, translator, '--no-portability-warnings', source,
                              '-o', output],
                             capture_output=True, text=True, timeout=60)
        wrote = os.path.exists(output)
    print(run.stderr, end='')
    if run.returncode == 0:
        problems.append('the translator accepted the file')
    if wrote:
        problems.append('the translator wrote an output file for a rejected input')
    wanted = f'{os.path.basename(source)}:{line}: {text}'
    if wanted not in run.stderr:
        problems.append(f'stderr does not contain "{wanted}"')
    return problems


def main(argv):
    if len(argv) >= 3 and argv[0] == 'failures':
        problems = check_failures(argv[1], argv[2:])
    elif len(argv) == 4 and argv[0] == 'rejected':
        problems = check_rejected(*argv[1:])
    else:
        print(__doc__, file=sys.stderr)
        return 2
    for problem in problems:
        print(f'CHECK FAILED: {problem}')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
