#!/usr/bin/env python3
"""pf2f90: translate a pFUnit ``.pf`` test module into plain Fortran 2008 for uniarc's ``funit``.

pFUnit cannot be installed everywhere uniarc is built, so this translator handles the subset of
pFUnit's preprocessor that uniarc's tests use (docs/testing.md lists it). The same ``.pf`` files
must also build with real pFUnit, so anything outside the subset is rejected rather than guessed at.

Usage::

    pf2f90.py INPUT.pf -o OUTPUT.f90
        Writes the test module (each @assert macro expanded into a call to the funit module,
        followed by a return on failure) and a small module ``<name>_suite`` whose
        ``<name>_run`` runs every @test of the file between its @before and @after procedures.

    pf2f90.py --driver OUTPUT.f90 MODULE [MODULE ...]
        Writes the main program of one test executable: it runs the suites of the given test modules
        and stops with a non-zero exit code if any test failed.

Errors are reported as ``file.pf:LINE: message`` on stderr with exit status 1.

Standard library only: the fallback must work on any machine with python3.
"""

import argparse
import os
import re
import sys

# Each supported assertion: the funit procedure it becomes, the names of its leading positional
# operands, which operand names may follow positionally (pFUnit's order), and the keywords it takes.
ASSERTIONS = {
    'true': ('funit_assert_true', ['condition'], ['message'], {'message'}),
    'false': ('funit_assert_false', ['condition'], ['message'], {'message'}),
    'isfinite': ('funit_assert_is_finite', ['value'], ['message'], {'message'}),
    'equal': ('funit_assert_equal', ['expected', 'actual'], ['tolerance', 'message'],
              {'tolerance', 'message'}),
    'relativelyequal': ('funit_assert_relatively_equal', ['expected', 'actual'],
                        ['tolerance', 'message'], {'tolerance', 'message'}),
    'lessthan': ('funit_assert_less_than', ['lhs', 'rhs'], [], {'message'}),
    'lessthanorequal': ('funit_assert_less_than_or_equal', ['lhs', 'rhs'], [], {'message'}),
    'greaterthan': ('funit_assert_greater_than', ['lhs', 'rhs'], [], {'message'}),
    'greaterthanorequal': ('funit_assert_greater_than_or_equal', ['lhs', 'rhs'], [], {'message'}),
}

# Keywords an assertion cannot do without (pFUnit has no relative comparison without a tolerance).
REQUIRED_KEYWORDS = {'relativelyequal': {'tolerance'}}

# The longest line we emit before continuing it: well under the 132 characters of the standard, so
# the generated code builds without -ffree-line-length-none.
MAX_LINE = 100

# Fortran names are at most 63 characters (F2008 3.2.2).
MAX_NAME = 63


class TranslationError(Exception):
    """A problem in the .pf file, located by file and line."""

    def __init__(self, filename, line, message):
        super().__init__(f'{filename}:{line}: {message}')


def split_code_comment(text, quote):
    """Split one physical line into its code and whether it ends inside a character context.

    ``quote`` is the delimiter of a character context continued from the previous line (or None).
    A ``!`` starts a comment only outside quotes; inside quotes a doubled delimiter is literal.
    Returns (code, quote_at_end).
    """
    i = 0
    while i < len(text):
        c = text[i]
        if quote:
            if c == quote:
                if i + 1 < len(text) and text[i + 1] == quote:
                    i += 2
                    continue
                quote = None
        elif c in ('"', "'"):
            quote = c
        elif c == '!':
            return text[:i], None
        i += 1
    return text, quote


def split_arguments(text):
    """Split an argument list at top-level commas, respecting (), [] and quotes.

    Raises ValueError with a short reason if brackets or quotes do not balance.
    """
    args, depth, quote, start, i = [], 0, None, 0, 0
    closing = {')': '(', ']': '['}
    stack = []
    while i < len(text):
        c = text[i]
        if quote:
            if c == quote:
                if i + 1 < len(text) and text[i + 1] == quote:
                    i += 2
                    continue
                quote = None
        elif c in ('"', "'"):
            quote = c
        elif c in '([':
            stack.append(c)
            depth += 1
        elif c in ')]':
            if not stack or stack[-1] != closing[c]:
                raise ValueError(f"unbalanced '{c}'")
            stack.pop()
            depth -= 1
        elif c == ',' and depth == 0:
            args.append(text[start:i].strip())
            start = i + 1
        i += 1
    if quote:
        raise ValueError('unterminated character constant')
    if stack:
        raise ValueError(f"unclosed '{stack[-1]}'")
    last = text[start:].strip()
    if last or args:
        args.append(last)
    if any(a == '' for a in args):
        raise ValueError('empty argument')
    return args


def fortran_string(text):
    """A Fortran character literal holding ``text``."""
    return "'" + text.replace("'", "''") + "'"


def continue_long(line, indent):
    """Break ``line`` into pieces of at most MAX_LINE characters, joined by ``&``...``&``.

    A continuation line that starts with ``&`` resumes exactly where the previous one stopped, even
    inside a token or a character constant (F2008 3.3.2.4), so any split point is valid.
    """
    if len(line) <= MAX_LINE:
        return [line]
    pieces = []
    lead = indent + '      &'
    first = True
    while line:
        room = MAX_LINE - 1 - (0 if first else len(lead))
        pieces.append((line[:room] if first else lead + line[:room]) + '&')
        line = line[room:]
        first = False
        if len(lead) + len(line) <= MAX_LINE:
            pieces.append(lead + line)
            break
    return pieces


class Translator:
    """Translates one .pf file; ``run`` returns the Fortran source text."""

    def __init__(self, path, portability_warnings=True):
        self.path = path
        self.portability_warnings = portability_warnings
        self.basename = os.path.basename(path)
        self.expected_module = os.path.splitext(self.basename)[0]
        with open(path, encoding='utf-8') as handle:
            self.lines = handle.read().splitlines()
        self.out = []
        self.module = None
        self.module_line = 0
        self.tests = []            # (name, disabled)
        self.fixtures = {}         # 'before'/'after' -> procedure name
        self.pending = None        # what the next subroutine statement belongs to

    def error(self, line, message):
        return TranslationError(self.path, line, message)

    # ---- reading -------------------------------------------------------------------------------

    def logical_directive(self, index):
        """Join a directive starting at line ``index`` (0-based) with its continuation lines.

        Returns (text without comments and continuation marks, index of the last line used,
        whether a comment was removed).
        """
        raw = self.lines[index]
        code, quote = split_code_comment(raw, None)
        commented = len(code) < len(raw)
        text = code.rstrip()
        while text.endswith('&'):
            text = text[:-1]
            index += 1
            # Comment lines and blank lines may sit between continuation lines (F2008 3.3.2.4).
            while index < len(self.lines) and quote is None and \
                    re.match(r'\s*(!.*)?$', self.lines[index]):
                index += 1
            if index >= len(self.lines):
                raise self.error(index, 'continuation line missing at end of file')
            raw = self.lines[index]
            code, quote = split_code_comment(raw, quote)
            commented = commented or len(code) < len(raw)
            stripped = code.lstrip()
            if stripped.startswith('&'):
                text += stripped[1:].rstrip()
            else:
                text += ' ' + stripped.rstrip()
        return text.strip(), index, commented

    # ---- directives ----------------------------------------------------------------------------

    def expand_assertion(self, kind, written, argument_text, line, indent):
        procedure, operands, positional_extras, keywords = ASSERTIONS[kind]
        try:
            args = split_arguments(argument_text)
        except ValueError as reason:
            raise self.error(line, f'cannot parse the arguments of {written}: {reason}')
        positional, named = [], {}
        for arg in args:
            match = re.match(r'([A-Za-z]\w*)\s*=(?!=)\s*(.*)$', arg, re.DOTALL)
            if match:
                keyword = match.group(1).lower()
                if keyword not in keywords:
                    raise self.error(line, f"{written} takes no keyword argument '{keyword}='"
                                           f" (supported: {', '.join(sorted(keywords))})")
                if keyword in named:
                    raise self.error(line, f"{written}: '{keyword}=' given twice")
                named[keyword] = match.group(2)
            elif named:
                raise self.error(line, f'{written}: positional argument after a keyword argument')
            else:
                positional.append(arg)
        if len(positional) < len(operands):
            raise self.error(line, f"{written} needs {len(operands)} argument(s): "
                                   f"{', '.join(operands)}")
        extras = positional[len(operands):]
        names = positional_extras
        # A third positional argument of assertEqual is the tolerance or, when it is a character
        # constant, the message: pFUnit's generics tell the two apart by type, which a translator
        # cannot see, so a message in a variable must be passed as message=.
        if names[:1] == ['tolerance'] and extras and extras[0][0] in '\'"':
            names = ['message']
        if len(extras) > len(names):
            raise self.error(line, f'{written}: too many positional arguments '
                                   f"(pass the message as message='...')")
        actual = list(zip(operands, positional[:len(operands)])) + list(zip(names, extras))
        for keyword, _ in actual[len(operands):]:
            if keyword in named:
                raise self.error(line, f"{written}: '{keyword}' given twice")
        actual += list(named.items())
        missing = REQUIRED_KEYWORDS.get(kind, set()) - {k for k, _ in actual}
        if missing:
            raise self.error(line, f"{written} needs {', '.join(sorted(missing))}=")
        actual.append(('location', fortran_string(f'{self.basename}:{line}')))

        body = indent + '   '
        self.out.append(f'{indent}! {self.basename}:{line}: {written}')
        self.out.append(f'{indent}call {procedure}( &')
        for position, (keyword, value) in enumerate(actual):
            tail = ', &' if position < len(actual) - 1 else ')'
            self.out.extend(continue_long(f'{body}{keyword}={value}{tail}', body))
        self.out.append(f'{indent}if (funit_failed()) return')

    def directive(self, index):
        """Handle the directive starting at line ``index``; return the index of its last line."""
        line = index + 1
        text, last, commented = self.logical_directive(index)
        # pFUnit 4 matches a directive against the whole line: it would pass such lines to the
        # compiler untranslated.
        if self.portability_warnings and (last > index or commented):
            print(f'{self.path}:{line}: warning: pFUnit 4 takes a directive on one line without '
                  'a comment; this file builds with uniarc\'s translator only', file=sys.stderr)
        indent = re.match(r'\s*', self.lines[index]).group(0)
        match = re.match(r'@(\w+)\s*(.*)$', text, re.DOTALL)
        if not match:
            raise self.error(line, f"unsupported pFUnit directive '{text}'")
        written, name, rest = '@' + match.group(1), match.group(1).lower(), match.group(2).strip()

        if name.startswith('assert') and name[len('assert'):] in ASSERTIONS:
            if not (rest.startswith('(') and rest.endswith(')')):
                raise self.error(line, f'{written} must be followed by an argument list in '
                                       f'parentheses')
            self.expand_assertion(name[len('assert'):], written, rest[1:-1], line, indent)
        elif name == 'test':
            if rest and re.fullmatch(r'\(\s*\)', rest) is None:
                raise self.error(line, f"unsupported pFUnit directive '{written}{rest}'"
                                       ' (pFUnit 4 ignores @test options such as disable; put'
                                       ' @disable on the line after @test)')
            self.claim_next_subroutine('test', line, written)
            self.out.append(f'{indent}! {written}')
        elif name == 'disable' and not rest:
            if self.pending is None or self.pending[0] != 'test':
                raise self.error(line, '@disable must come between @test and its subroutine')
            self.pending = ('test', self.pending[1], True)
            self.out.append(f'{indent}! {written}')
        elif name in ('before', 'after') and not rest:
            if name in self.fixtures:
                raise self.error(line, f'a second @{name} (a suite has one)')
            self.claim_next_subroutine(name, line, written)
            self.out.append(f'{indent}! {written}')
        else:
            raise self.error(line, f"unsupported pFUnit directive '{written}'")
        return last

    def claim_next_subroutine(self, role, line, written):
        if self.pending is not None:
            raise self.error(line, f'{written} follows @{self.pending[0]} (line {self.pending[1]})'
                                   ' before its subroutine')
        if self.module is None:
            raise self.error(line, f'{written} outside a module (only module-style suites are'
                                   ' supported)')
        self.pending = (role, line, False)

    def subroutine(self, line, name, arguments):
        role, _, disabled = self.pending
        self.pending = None
        if arguments and arguments.strip('() \t'):
            raise self.error(line, f"'{name}' takes arguments: test-case style suites (@TestCase)"
                                   ' are not supported; tests and fixtures take no arguments')
        if role == 'test':
            self.tests.append((name, disabled))
        else:
            self.fixtures[role] = name

    # ---- the whole file ------------------------------------------------------------------------

    def run(self):
        index = 0
        while index < len(self.lines):
            raw = self.lines[index]
            line = index + 1
            if re.match(r'\s*@', raw):
                index = self.directive(index) + 1
                continue
            code, _ = split_code_comment(raw, None)
            module = re.match(r'\s*module\s+(\w+)\s*$', code, re.IGNORECASE)
            if module and module.group(1).lower() not in ('procedure', 'subroutine', 'function'):
                if self.module is not None:
                    raise self.error(line, 'a second module (one test module per file)')
                self.module, self.module_line = module.group(1), line
                if self.module.lower() != self.expected_module.lower():
                    raise self.error(line, f"module '{self.module}' must be named after its file"
                                           f" ('{self.expected_module}'), as pFUnit requires")
            elif self.pending is not None and code.strip():
                sub = re.match(r'\s*subroutine\s+(\w+)\s*(\(.*\))?\s*$', code, re.IGNORECASE)
                if not sub:
                    raise self.error(line, f'expected the subroutine of @{self.pending[0]}'
                                           f' (line {self.pending[1]})')
                self.subroutine(line, sub.group(1), sub.group(2))
            self.out.append(raw)
            index += 1
        if self.pending is not None:
            raise self.error(self.pending[1], f'@{self.pending[0]} without a subroutine')
        if self.module is None:
            raise self.error(1, 'no module: only module-style suites are supported')
        return self.render()

    def render(self):
        suite = f'{self.module}_suite'
        run = f'{self.module}_run'
        if len(suite) > MAX_NAME:
            raise self.error(self.module_line, f"module name '{self.module}' is too long")
        used = sorted({name for name, disabled in self.tests if not disabled} |
                      set(self.fixtures.values()))
        fixtures = ''.join(f', {role}={self.fixtures[role]}' for role in ('before', 'after')
                           if role in self.fixtures)
        text = [f'! Generated by pf2f90.py from {self.basename}: do not edit; edit the .pf file.',
                '! Assertions are expanded in place; "if (funit_failed()) return" makes the first',
                '! failing assertion end its procedure, as in pFUnit.']
        text += self.out
        text += ['',
                 f'!> Runs the tests of {self.basename} (generated by pf2f90.py).',
                 f'module {suite}',
                 '   use funit, only: funit_runner_t, funit_run_test, funit_skip_test']
        if used:
            text += continue_long(f"   use {self.module}, only: {', '.join(used)}", '   ')
        text += ['   implicit none',
                 '   private',
                 f'   public :: {run}',
                 'contains',
                 f'   !> Run every @test of {self.basename}, in file order.',
                 f'   subroutine {run}(runner)',
                 '      type(funit_runner_t), intent(inout) :: runner']
        for name, disabled in self.tests:
            label = fortran_string(f'{self.module}.{name}')
            if disabled:
                text.append(f'      call funit_skip_test(runner, {label})')
            else:
                call = f'      call funit_run_test(runner, {label}, {name}{fixtures})'
                text += continue_long(call, '      ')
        text += [f'   end subroutine {run}', f'end module {suite}', '']
        return '\n'.join(text)


def driver_source(modules):
    """The main program that runs the suites of ``modules`` and exits non-zero on failure."""
    text = ['! Generated by pf2f90.py: the driver of one pFUnit-style test executable.',
            '!> Runs the test suites and stops with exit code 1 if any test failed.',
            'program funit_driver',
            '   use funit, only: funit_runner_t, funit_finish']
    text += [f'   use {module}_suite, only: {module}_run' for module in modules]
    text += ['   implicit none',
             '   type(funit_runner_t) :: runner',
             '   logical :: success']
    text += [f'   call {module}_run(runner)' for module in modules]
    text += ['   call funit_finish(runner, success)',
             '   if (.not. success) stop 1',
             'end program funit_driver',
             '']
    return '\n'.join(text)


def write_if_changed(path, text):
    """Write ``text`` to ``path`` unless it already holds it (keeps rebuilds minimal)."""
    try:
        with open(path, encoding='utf-8') as handle:
            if handle.read() == text:
                return
    except OSError:
        pass
    with open(path, 'w', encoding='utf-8') as handle:
        handle.write(text)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('inputs', nargs='+', metavar='INPUT',
                        help='a .pf file, or with --driver the names of the test modules')
    parser.add_argument('-o', '--output', help='the Fortran file to write (translation mode)')
    parser.add_argument('--driver', metavar='OUTPUT', help='write the driver program instead')
    parser.add_argument('--no-portability-warnings', action='store_true',
                        help='accept silently what real pFUnit would not (directives over '
                             'several lines or with a comment)')
    options = parser.parse_args(argv)
    try:
        if options.driver:
            for module in options.inputs:
                if not re.fullmatch(r'[A-Za-z]\w*', module):
                    raise ValueError(f"'{module}' is not a Fortran module name")
            write_if_changed(options.driver, driver_source(options.inputs))
        else:
            if len(options.inputs) != 1 or not options.output:
                parser.error('translation needs one INPUT.pf and -o OUTPUT.f90')
            translator = Translator(options.inputs[0], not options.no_portability_warnings)
            write_if_changed(options.output, translator.run())
    except (TranslationError, ValueError, OSError) as problem:
        print(problem, file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
