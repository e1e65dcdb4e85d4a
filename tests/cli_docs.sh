#!/bin/bash
# README.md and docs/*.md: no paragraph kept twice (each text has one home;
# README is the entrance, the rest lives in docs/), every relative link and
# image resolves, README stays at most 300 lines and shows every bundled
# scene's gallery picture.
# usage: bash tests/cli_docs.sh /path/to/specmip   (the binary is not used)
source "$(dirname "$0")/lib_cli.sh"
CHECK=$ROOT/tools/docs_check.py
check "no paragraph in README.md and docs/ twice" python3 "$CHECK" dup "$ROOT"
check "every relative link in README.md and docs/ resolves" python3 "$CHECK" links "$ROOT"
lines=$(wc -l < "$ROOT/README.md")
check "README.md at most 300 lines (has $lines)" num "$lines" '<=' 300
check "README.md has its two commands" grep -q '^bash tools/test.sh' "$ROOT/README.md"
# the gallery: every bundled scene's picture is there and shown (tools/gallery.sh)
for f in "$ROOT"/scenes/*.scene; do
    n=$(basename "$f" .scene)
    check "gallery: docs/gallery/$n.png is there" test -s "$ROOT/docs/gallery/$n.png"
    check "gallery: README shows $n" grep -qF "(docs/gallery/$n.png)" "$ROOT/README.md"
done

# The checks see what they are for: a copy of the documents with one of README's
# paragraphs pasted into a doc, and with a link to a missing file, must fail.
mkdir -p "$T/r/docs"
cp "$ROOT/README.md" "$T/r/" && cp "$ROOT"/docs/*.md "$T/r/docs/"
ln -s "$ROOT/docs/gallery" "$T/r/docs/gallery" 2> /dev/null
para=$(python3 -c "import sys; sys.path.insert(0, sys.argv[1]); import docs_check
print(next(p for _, p in docs_check.paragraphs(sys.argv[2]) if len(p) > 200 and p[0] not in '|#<!'))" \
    "$ROOT/tools" "$ROOT/README.md")
check "README.md has a paragraph to copy" test -n "$para"
printf '\n%s\n' "$para" >> "$T/r/docs/METHODS.md"
check "a paragraph copied from README into docs/ is found" \
    bash -c "! python3 '$CHECK' dup '$T/r' > '$T/dup.txt' && grep -q 'docs/METHODS.md' '$T/dup.txt'"
cp "$ROOT/docs/METHODS.md" "$T/r/docs/METHODS.md"
echo 'See [the missing page](NOPE.md) and [a heading](METHODS.md#no-such-heading).' >> "$T/r/docs/SCENES.md"
check "a link to a missing file and to a missing heading are found" \
    bash -c "! python3 '$CHECK' links '$T/r' > '$T/links.txt' && grep -q 'NOPE.md' '$T/links.txt' \
             && grep -q 'no-such-heading' '$T/links.txt'"
finish
