#!/usr/bin/env bash
# Makes docs/gallery.md and docs/gallery/NAME.png: a picture of every example recipe, drawn by
# `blocksmith render` (CPU, the same bytes on every machine). script/cli/tests/gallery.rs checks that
# the pictures are current; run this after changing a recipe.
#   bash docs/gallery.sh              # builds the debug binary first
#   BLOCKSMITH=path/to/blocksmith bash docs/gallery.sh
set -euo pipefail
cd "$(dirname "$0")/.."
if [ -z "${BLOCKSMITH:-}" ]; then
  cargo build --workspace --bin blocksmith
  BLOCKSMITH=target/debug/blocksmith
fi
size=320x240
rm -f docs/gallery/*.png
{
  echo "# Gallery"
  echo
  echo "Every recipe in \`examples/\` at its default parameters, drawn by"
  echo "\`blocksmith render examples/NAME.rhai -o docs/gallery/NAME.png --size $size\` (made by"
  echo "\`docs/gallery.sh\`; \`script/cli/tests/gallery.rs\` keeps it current). Colours are the model's own"
  echo "(\`m.color(…)\`, feature and block colours), else a plain grey-blue."
  echo
  for recipe in examples/[!_]*.rhai; do
    name=$(basename "$recipe" .rhai)
    # Recipes print their checks; the gallery keeps only the picture (errors still stop it).
    "$BLOCKSMITH" render "$recipe" -o "docs/gallery/$name.png" --size "$size" >/dev/null 2>&1 ||
      "$BLOCKSMITH" render "$recipe" -o "docs/gallery/$name.png" --size "$size"
    # The recipe's opening comment paragraph says what it builds.
    what=$(awk '/^\/\/ *$/ || !/^\/\// { exit } { sub(/^\/\/ */, ""); printf "%s ", $0 }' "$recipe" | sed 's/ *$//')
    echo "## $name"
    echo
    echo "$what"
    echo
    echo "![$name](gallery/$name.png)"
    echo
  done
} > docs/gallery.md
echo "wrote docs/gallery.md and $(ls docs/gallery/*.png | wc -l) pictures"
