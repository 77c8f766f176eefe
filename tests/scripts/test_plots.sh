#!/usr/bin/env bash
# Test of scripts/plot_path.sh and scripts/plot_shapes.sh: each must write a PNG (checked by its
# signature and a size that only a drawn picture reaches) from uniarc's files, and refuse a column
# that the path file does not have (exit 2). Skipped (77) without gnuplot.
#   test_plots.sh UNIARC WORKDIR
set -euo pipefail
uniarc=$1 work=$2
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
command -v gnuplot >/dev/null 2>&1 || { echo "gnuplot not installed: skipped"; exit 77; }
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*"; exit 1; }
png_ok() {
  [ -f "$1" ] || fail "$1 not written"
  [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "$1 is not a PNG"
  # an empty 1000x700 canvas with axes only compresses to a few kB; curves and legend add more
  [ "$(wc -c < "$1")" -gt 10000 ] || fail "$1 is only $(wc -c < "$1") bytes"
  echo "ok: $1 ($(wc -c < "$1") bytes)"
}
"$uniarc" "$source_dir/input/ring_rigid_cavity.inp" -o ring -D n=20 -q
"$uniarc" "$source_dir/input/ring_rigid_cavity.inp" -o springs -D n=20 -D k=1e4 -q
bash "$source_dir/scripts/plot_path.sh" -o paths.png ring/ring_rigid_cavity.path springs/ring_rigid_cavity.path
png_ok paths.png
bash "$source_dir/scripts/plot_path.sh" -x s_contact_1 -C ring/ring_rigid_cavity.path
png_ok ring/ring_rigid_cavity.png
bash "$source_dir/scripts/plot_shapes.sh" -f 5 -s 10,40 -o shapes.png ring/ring_rigid_cavity.shape
png_ok shapes.png
code=0
bash "$source_dir/scripts/plot_path.sh" -x no_such_column -o never.png ring/ring_rigid_cavity.path || code=$?
[ "$code" = 2 ] && [ ! -e never.png ] || fail "unknown column: exit $code, expected 2 and no picture"
code=0
bash "$source_dir/scripts/plot_shapes.sh" -s 7 -o never.png ring/ring_rigid_cavity.shape || code=$?
[ "$code" = 2 ] && [ ! -e never.png ] || fail "missing snapshot: exit $code, expected 2 and no picture"
echo ok
