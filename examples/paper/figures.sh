#!/usr/bin/env bash
# Regenerates every figure in examples/paper/figures/ (SVG) from the scenarios here and
# examples/compare.toml, and prints the summary lines and tables quoted in README.md.
#   examples/paper/figures.sh            # from the repository root; a release build, then under a minute on 2 cores
#   examples/paper/figures.sh --maps     # also the two 1,000,000-start maps (map-*.toml,
#                                        # --fast): about 40 min more on 2 cores
set -euo pipefail
maps=false
if [ "${1:-}" = "--maps" ]; then maps=true; fi
cd "$(dirname "$0")/../.."
cargo build --release -q -p wmr-cli
w=./target/release/wmr-cli
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
figs=examples/paper/figures
mkdir -p "$figs"

for f in fig4 fig5 fig6 fig6-bidirectional fig7; do
  echo "== $f"
  "$w" run "examples/paper/$f.toml" -o "$out/$f.csv"
  "$w" plot "examples/paper/$f.toml" -o "$out/$f" 2>/dev/null
done
cp "$out/fig4/paths.svg" "$figs/fig4-paths.svg"
cp "$out/fig5/paths.svg" "$figs/fig5-paths.svg"
cp "$out/fig6/paths.svg" "$figs/fig6-paths.svg"
cp "$out/fig6-bidirectional/paths.svg" "$figs/fig6-bidirectional-paths.svg"
cp "$out/fig7/paths.svg" "$figs/fig7-path.svg"
cp "$out/fig7/run0-wheel-speeds.svg" "$figs/fig8-wheel-speeds.svg"
cp "$out/fig7/run0-errors.svg" "$figs/fig9-errors.svg"

echo "== compare-paths"
"$w" plot examples/paper/compare-paths.toml -o "$out/compare-paths" 2>/dev/null
cp "$out/compare-paths/compare-start0.svg" "$figs/compare-paths-0deg.svg"
cp "$out/compare-paths/compare-start1.svg" "$figs/compare-paths-180deg.svg"

echo "== compare (1,000 starts x 4 laws, 180 s)"
"$w" sweep examples/compare.toml -o "$out/compare.csv" --plots "$out/compare"
for law in paper paper_bidirectional polar lyapunov; do
  cp "$out/compare/region-$law.svg" "$figs/region-$law.svg"
done
if $maps; then
  for law in paper_bidirectional paper; do
    echo "== map-$law (1,000,000 starts, --fast)"
    "$w" sweep "examples/paper/map-$law.toml" --fast -o "$out/map-$law.csv" --plots "$out/map-$law"
    cp "$out/map-$law/region-$law.svg" "$figs/map-$law.svg"
  done
fi
echo "figures written to $figs"
