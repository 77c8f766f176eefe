"""Reading uniarc's result tables (docs/contracts.md) for the scripts of this folder.

A table (STEM.path, STEM.crit, STEM.shape, STEM.surface) has its column names on the first line, then
the run's provenance as `#` comment lines (`# uniarc VERSION`, `# deck: PATH`, `# defines: NAME=VALUE
...` or `none`, `# utc: TIME`), then rows of whitespace-separated fields; blank lines separate the
snapshots of STEM.shape.
"""
import os


class Table:
    """A table: `names` (column names), `rows` (lists of field strings, blank lines dropped),
    `snapshots` (the rows split at blank lines), `provenance` (dict of the `# key: value` lines; the
    first line's version under 'version') and `defines` (dict NAME -> VALUE of the run's -D)."""

    def __init__(self, path):
        self.path = path
        with open(path) as handle:
            lines = handle.read().splitlines()
        if not lines or not lines[0].strip() or lines[0].startswith('#'):
            raise ValueError(f'{path}: no header line of column names (not a uniarc table)')
        self.names = lines[0].split()
        self.provenance, self.rows, self.snapshots = {}, [], [[]]
        for line in lines[1:]:
            if line.startswith('#'):
                text = line[1:].strip()
                key, colon, value = text.partition(':')
                if colon and ' ' not in key:
                    self.provenance[key] = value.strip()
                elif text.startswith('uniarc '):
                    self.provenance['version'] = text
                continue
            fields = line.split()
            if not fields:
                if self.snapshots[-1]:
                    self.snapshots.append([])
                continue
            if len(fields) == len(self.names):
                self.rows.append(fields)
                self.snapshots[-1].append(fields)
        if not self.snapshots[-1]:
            self.snapshots.pop()
        text = self.provenance.get('defines', 'none')
        self.defines = dict(item.split('=', 1) for item in text.split() if '=' in item) if text != 'none' else {}

    def column(self, name):
        """0-based index of a column by name, or None."""
        return self.names.index(name) if name in self.names else None

    def numbers(self, rows=None):
        """The rows as floats (a text column, as STEM.crit's kind, stays text)."""
        def number(text):
            try:
                return float(text)
            except ValueError:
                return text
        return [[number(x) for x in row] for row in (self.rows if rows is None else rows)]

    @property
    def stem(self):
        return os.path.splitext(os.path.basename(self.path))[0]
