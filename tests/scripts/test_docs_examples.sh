#!/usr/bin/env bash
# Every example of README.md's tour and of docs/sweeps.md runs as shown, in the order shown: the
# ```sh blocks (but the set-up's quickstart.sh and test.sh, which build), then README's ```python and
# ```gnuplot blocks of the tables' readers, in a scratch folder that has the tree's input/ and scripts/
# and the uniarc under test as build/uniarc. The Slurm example runs with the fake sbatch of
# tests/scripts/fake_slurm. Each picture an example makes must be a PNG. A block that refers to a
# file a later block makes fails here. The Walker arch deck of docs/input.md (*FOUNDATION) must give
# the critical points its text states.
#   test_docs_examples.sh UNIARC WORKDIR
set -euo pipefail
uniarc=$1 work=$2
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
command -v gnuplot >/dev/null 2>&1 || { echo "gnuplot not installed: skipped"; exit 77; }
rm -rf "$work" && mkdir -p "$work/build" && cd "$work"
fail() { echo "FAIL: $*"; exit 1; }
ln -s "$source_dir/input" input
ln -s "$source_dir/scripts" scripts
ln -s "$uniarc" build/uniarc
export PATH="$source_dir/tests/scripts/fake_slurm:$PATH" FAKE_SBATCH_LOG=$work/slurm/fake_sbatch.log
mkdir -p slurm
python=""
for candidate in python3 /usr/bin/python3; do
  if "$candidate" -c 'import numpy, pandas' 2>/dev/null; then python=$candidate; break; fi
done
[ -n "$python" ] || fail "no python3 with numpy and pandas (scripts/install_deps.sh)"

# the blocks: FILE LANGUAGE, then the block's text, NUL-terminated
python3 - "$source_dir/README.md" "$source_dir/docs/sweeps.md" > blocks <<'PYTHON'
import re, sys
for name in sys.argv[1:]:
    text = open(name).read()
    for language, body in re.findall(r'^```(sh|python|gnuplot)\n(.*?)^```', text, re.S | re.M):
        if language == 'sh' and ('scripts/quickstart.sh' in body or 'scripts/test.sh' in body):
            continue   # the set-up block builds the program; the test has it already
        sys.stdout.write(f'{name.split("/")[-1]} {language}\n{body}\0')
PYTHON
count=0
while IFS= read -r -d '' block; do
  count=$((count + 1))
  where=${block%%$'\n'*} body=${block#*$'\n'}
  echo "--- block $count ($where)"
  printf '%s' "$body"
  case ${where#* } in
    sh) printf 'set -euo pipefail\n%s' "$body" > "block$count.sh"; bash "block$count.sh" > "block$count.log" 2>&1 \
          || { cat "block$count.log"; fail "block $count of $where"; } ;;
    python) printf '%s' "$body" | "$python" > "block$count.log" 2>&1 || { cat "block$count.log"; fail "block $count of $where"; } ;;
    gnuplot) { echo 'set terminal dumb'; printf '%s' "$body"; } | gnuplot > "block$count.log" 2>&1 \
               && ! grep -qi 'warning\|error' "block$count.log" || { cat "block$count.log"; fail "block $count of $where"; } ;;
  esac
done < blocks
[ "$count" -ge 7 ] || fail "only $count example blocks found"
for png in $(find . -name '*.png' -newer blocks); do
  [ "$(head -c 8 "$png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "$png is not a PNG"
done
echo "ok: $count blocks ran in order; $(find . -name '*.png' -newer blocks | wc -l) pictures"

# docs/input.md's Walker arch (*FOUNDATION, ex. 2) is a deck of its own: it must be Walker's arch, with
# the critical points the text below it states (to the 4 significant digits written there)
python3 - "$source_dir/docs/input.md" <<'PYTHON' > walker_input.inp
import re, sys
text = open(sys.argv[1]).read()
print(re.search(r"^```(?:deck)?\n(\*\* Ex\. 2: Walker's arch.*?)^```", text, re.S | re.M).group(1), end='')
PYTHON
"$uniarc" walker_input.inp -o walker_input -q
"$uniarc" walker_input.inp -o walker_input_free -q -D k=0
python3 - "$source_dir/docs/input.md" <<'PYTHON'
import re, sys
text = open(sys.argv[1]).read()
said = re.search(r'symmetric limit point at λ = ([\d.]+) and, before it, a bifurcation into the\s+'
                 r'antisymmetric mode at λ = ([\d.]+) \(`STEM.crit`; with `-D k=0`: ([\d.]+) and ([\d.]+)\)', text)
if not said:
    sys.exit('FAIL: docs/input.md no longer states the Walker arch critical points as this test reads them')
limit, bifurcation, free_limit, free_bifurcation = map(float, said.groups())


def first(folder, kind):
    lines = [l.split() for l in open(f'{folder}/walker_input.crit').read().splitlines()[1:] if l and l[0] != '#']
    return next(float(l[2]) for l in lines if l[0] == kind)


got = [first('walker_input', 'limit_max'), first('walker_input', 'bifurcation'),
       first('walker_input_free', 'limit_max'), first('walker_input_free', 'bifurcation')]
for stated, value in zip((limit, bifurcation, free_limit, free_bifurcation), got):
    if f'{value:.4g}' != f'{stated:.4g}':
        sys.exit(f'FAIL: docs/input.md says {stated}, the deck gives {value!r}')
print('docs/input.md Walker arch: limit, bifurcation (k = 1e4, k = 0) as stated:', got)
PYTHON
