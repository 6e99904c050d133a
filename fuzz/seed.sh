#!/bin/sh
# Seeds the fuzz corpora (copied at run time: corpora are not committed).
# Run from anywhere. `parse` and `check`: the example components and the
# test fixtures of the LANGUAGE.md dialect; `genom3`: the real components
# of the GenoM3 corpus (../shared/corpus/genom3 next to the repository, or
# $GENOM3_CORPUS) and the GenoM3 front-end's fixtures; `generated` starts
# empty (its inputs are generator configurations).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
copy() { # copy TARGET DIR...: one file per distinct content, named after its checksum
    target=$1; shift
    dir="$here/corpus/$target"
    mkdir -p "$dir"
    find "$@" -name '*.gen' -o -name '*.idl' -o -name '*.h' |
        while read -r f; do
            sum=$(cksum < "$f" | cut -d' ' -f1)
            cp "$f" "$dir/seed-$sum"
        done
}
for target in parse check; do
    copy "$target" "$root/specs" "$root/tests/fixtures"
done
corpus=${GENOM3_CORPUS:-$root/../shared/corpus/genom3}
if [ -d "$corpus" ]; then
    copy genom3 "$corpus" "$root/parser/genom3/tests/fixtures"
else
    copy genom3 "$root/parser/genom3/tests/fixtures"
fi
mkdir -p "$here/corpus/generated"
for t in parse check genom3 generated; do
    echo "$t: $(ls "$here/corpus/$t" | wc -l) seed files"
done
