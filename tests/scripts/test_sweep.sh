#!/usr/bin/env bash
# Test of scripts/sweep.sh: a two-value sweep of ex. 1 (-D n=20, coarse on purpose: this checks the
# tooling, not the mechanics) with k = 0 (rigid cavity) and k = bad, which uniarc must refuse (exit 2).
# sweep.tsv must have one row per value in the given order, the failed one included, and the numbers
# of the good row must be those of its own STEM.crit and STEM.path. A second sweep into the same
# folder must be refused (exit 2, nothing changed), and with --replace leave no value folder of the
# first one behind.
#   test_sweep.sh UNIARC WORKDIR
set -euo pipefail
uniarc=$1 work=$2
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*"; exit 1; }

bash "$source_dir/scripts/sweep.sh" "$source_dir/input/ring_rigid_cavity.inp" k 0 bad -D n=20 \
  --uniarc "$uniarc" --no-plot
dir=sweep_ring_rigid_cavity_k
tsv=$dir/sweep.tsv
[ -f "$tsv" ] || fail "no $tsv"
cat "$tsv"
[ "$(wc -l < "$tsv")" -eq 3 ] || fail "sweep.tsv: $(wc -l < "$tsv") lines, expected a header and 2 rows"
[ "$(head -n 1 "$tsv")" = "$(printf 'value\tlambda_limit\tv_crown\ts_contact_1\ts_contact_2\tstatus')" ] \
  || fail "header: $(head -n 1 "$tsv")"
IFS=$'\t' read -r value load crown s1 s2 status < <(sed -n 2p "$tsv")
[ "$value" = 0 ] && [ "$status" = ok ] || fail "row 1: value $value status $status, expected 0 ok"
IFS=$'\t' read -r bvalue bload _ _ _ bstatus < <(sed -n 3p "$tsv")
[ "$bvalue" = bad ] && [ "$bstatus" = 'failed(2)' ] && [ "$bload" = nan ] \
  || fail "row 2: $bvalue $bload $bstatus, expected bad nan failed(2)"
[ "$(cat "$dir/bad/exit_code")" = 2 ] || fail "bad/exit_code is not 2"
grep -q "k=bad" "$dir/bad/uniarc.log" || fail "bad/uniarc.log does not hold uniarc's message"

# the good row against its own files: lambda and v_crown of the first limit_max of STEM.crit, and the
# contact ends of the path interpolated at the event's fractional step
python3 - "$dir/0" "$load" "$crown" "$s1" "$s2" <<'PYTHON'
import sys
run, load, crown, s1, s2 = sys.argv[1], *map(float, sys.argv[2:])
def data(name):
    """Rows of a uniarc table: after the header line, without the `#` provenance lines."""
    return [l.split() for l in open(f'{run}/{name}').read().splitlines()[1:] if l.strip() and l[0] != '#']
first = next(r for r in data('ring_rigid_cavity.crit') if r[0] == 'limit_max')
step, lam, v = map(float, first[1:4])
names = open(f'{run}/ring_rigid_cavity.path').readline().split()
rows = [list(map(float, r)) for r in data('ring_rigid_cavity.path')]
before = max(r for r in rows if r[0] <= step)
after = min(r for r in rows if r[0] >= step)
t = (step - before[0]) / (after[0] - before[0]) if after[0] > before[0] else 0.0
expected = {'lambda': lam, 'v_crown': v}
for name in ('s_contact_1', 's_contact_2'):
    i = names.index(name)
    expected[name] = before[i] + t * (after[i] - before[i])
got = {'lambda': load, 'v_crown': crown, 's_contact_1': s1, 's_contact_2': s2}
# sweep.tsv prints 10 significant digits: agreement to 1e-9 relative
bad = [k for k in got if abs(got[k] - expected[k]) > 1e-9 * max(abs(expected[k]), 1e-30)]
print('sweep.tsv vs STEM.crit/STEM.path:', {k: (got[k], expected[k]) for k in got})
# a limit load of ex. 1 must lie on the rising part of the path: above 0, below the deck's stop (120)
if bad or not 0.0 < load < 120.0:
    sys.exit(f'FAIL: {bad or "limit load out of range"}')
PYTHON

# the folder exists: refused, untouched
code=0
bash "$source_dir/scripts/sweep.sh" "$source_dir/input/ring_rigid_cavity.inp" k 1e4 -D n=20 \
  --uniarc "$uniarc" --no-plot 2>refused.txt || code=$?
cat refused.txt
[ "$code" = 2 ] || fail "a sweep into an existing sweep folder: exit $code, expected 2"
grep -q -- "--replace" refused.txt || fail "the refusal does not name --replace"
[ -d "$dir/bad" ] && [ "$(cat "$dir/values.txt")" = "$(printf '0\nbad')" ] || fail "the refused sweep changed $dir"
# --replace: the earlier value folders go; --label is kept for the plots
bash "$source_dir/scripts/sweep.sh" "$source_dir/input/ring_rigid_cavity.inp" k 0 -D n=20 \
  --uniarc "$uniarc" --no-plot --replace --label 0=rigid
[ ! -e "$dir/bad" ] || fail "--replace left the value folder bad of the earlier sweep"
[ "$(cut -f1,6 "$dir/sweep.tsv" | tr '\t\n' ' ')" = "value status 0 ok " ] || fail "sweep.tsv after --replace: $(cat "$dir/sweep.tsv")"
[ "$(cat "$dir/labels.txt")" = "0=rigid" ] || fail "labels.txt: $(cat "$dir/labels.txt")"
# a folder that is not a sweep's is never deleted
mkdir -p other/sweep_ring_rigid_cavity_k && touch other/sweep_ring_rigid_cavity_k/keep
code=0
bash "$source_dir/scripts/sweep.sh" "$source_dir/input/ring_rigid_cavity.inp" k 0 -D n=20 -o other \
  --uniarc "$uniarc" --no-plot --replace || code=$?
[ "$code" = 2 ] && [ -f other/sweep_ring_rigid_cavity_k/keep ] || fail "--replace on a folder without sweep.conf: exit $code"
echo ok
