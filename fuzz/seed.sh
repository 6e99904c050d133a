#!/bin/sh
# Seeds the fuzz corpora from the example components and the test fixtures
# (copied at run time: corpora are not committed). Run from anywhere.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
for target in parse check; do
    dir="$here/corpus/$target"
    mkdir -p "$dir"
    find "$root/specs" "$root/tests/fixtures" -name '*.gen' -o -name '*.idl' |
        while read -r f; do
            # One file per distinct content: name it after its checksum.
            sum=$(cksum < "$f" | cut -d' ' -f1)
            cp "$f" "$dir/seed-$sum"
        done
done
echo "seeded: $(ls "$here/corpus/parse" | wc -l) files per target"
