#!/bin/sh
# Seeds the fuzz corpora (copied at run time: corpora are not committed).
# Run from anywhere. `parse` and `check`: the example components and the
# test fixtures of the LANGUAGE.md dialect; `genom3`: the real components
# of the GenoM3 corpus (../shared/corpus/genom3 next to the repository, or
# $GENOM3_CORPUS) and the GenoM3 front-end's fixtures; `generated` starts
# empty (its inputs are generator configurations); `wcet`: the WCET files
# of the tests. Then small generated seeds (a few KB) of the hostile shapes
# of issue 28 round 3 (docs/limits.md): deep nesting just within and past
# the parsers' guards (GenoM3 1024 levels, dialect 64), long and nested
# constant expressions, long `#if` conditions, numbers out of range,
# durations over one day, `>>`, include diamonds, long lines, many
# diagnostics, control characters and byte-order marks, hostile WCET lines.
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
    copy genom3 "$corpus" "$root/genom3-frontend/tests/fixtures"
else
    copy genom3 "$root/genom3-frontend/tests/fixtures"
fi
mkdir -p "$here/corpus/generated"

# --- generated seeds of the hostile shapes ---------------------------------
rep() { # rep TEXT N: TEXT N times (awk escapes such as \n apply)
    awk -v s="$1" -v n="$2" 'BEGIN { for (i = 0; i < n; i++) printf "%s", s }'
}
shape() { # shape NAME TARGET...: standard input as seed `shape-NAME` of each TARGET
    name=$1; shift
    tmp="$here/corpus/.shape.tmp"
    cat > "$tmp"
    for target in "$@"; do
        mkdir -p "$here/corpus/$target"
        cp "$tmp" "$here/corpus/$target/shape-$name"
    done
    rm -f "$tmp"
}
task='  task t { period 10 ms; };\n'
g3() { # g3 BODY: a GenoM3 component `c` with task `t` around BODY
    printf 'component c {\n%s\n  task t { period 10 ms; };\n};\n' "$1"
}

# GenoM3 (target genom3). Nesting within and past the 1024-level guard.
for n in 300 1100; do
    { rep 'module m{' "$n"; printf 'const long k = 1;'; rep '};' "$n"
      printf '\ncomponent c {\n%b};\n' "$task"; } | shape "g3-modules-$n" genom3
done
for n in 300 1100; do
    { printf 'struct s{'; rep 'struct s{' "$n"; printf 'long x;'; rep '} f;' "$n"
      printf '};\ncomponent c {\n%b};\n' "$task"; } | shape "g3-structs-$n" genom3
done
# Long and nested constant expressions (bound: 4096 terms).
g3 "  const long k = $(rep '1+' 2000)1;" | shape g3-flat-2000 genom3
g3 "  const long k = $(rep '1+(' 600)1$(rep ')' 600);" | shape g3-nested-600 genom3
g3 "  const long k = $(rep '(' 1100)1$(rep ')' 1100);" | shape g3-parens-1100 genom3
g3 "  const long k = $(rep '(' 500)1$(rep ' >> 1)' 500);" | shape g3-shifts-500 genom3
# `#if` conditions read in one pass.
{ printf '#if %s1\n#endif\n' "$(rep '!' 2000)"; g3 ''; } | shape g3-if-bangs genom3
{ printf '#if %s0\n' "$(rep '!' 2001)"; g3 ''; printf '#endif\n'; } | shape g3-if-bangs-hidden genom3
{ printf '#if %s1\n' "$(rep '0||' 1000)"; g3 ''; printf '#endif\n'; } | shape g3-if-or genom3
{ printf '#if %s\n' "$(rep '(' 1100)1$(rep ')' 1100)"; g3 ''; printf '#endif\n'; } | shape g3-if-parens genom3
# Numbers out of range.
g3 '  const short s = 70000;
  const octet o = 300;
  const unsigned long u = -1;
  const double d = 1e999;
  const long long ll = 9223372036854775807 + 1;
  const long x = 999999999999999999999999999999999999999999;
  const long sh = 1 << 70;
  typedef long big[100000000000000000000];' | shape g3-numbers genom3
printf 'component c {\n  task a { period 1e30 s; };\n  task b { period 0.0000000001 ms; };\n  task d { period (1 << 70) ms; };\n  task e { period 99999999999999999999999 ms; };\n  task f { period 86400 s; };\n};\n' |
    shape g3-periods genom3
g3 '  ids { sequence<sequence<long>> a; sequence<sequence<long> > b; };
  const long r = 256 >> 4 >> 2;
  const long l = 1 << 62;' | shape g3-shift-close genom3
# Includes: a diamond (both sides include interface.gen) and a chain.
printf '#include "left.gen"\n#include "right.gen"\n#include "interface.gen"\ncomponent c {\n  provides i;\n%b};\n' "$task" |
    shape g3-include-diamond genom3
printf '#include "interface.gen"\n#include "interface.gen"\n#include "self.gen"\ncomponent c {\n%b};\n' "$task" |
    shape g3-include-chain genom3
# A long line, many diagnostics, control characters and a byte-order mark.
g3 "  const long $(rep 'a' 3000) = 1;" | shape g3-long-line genom3
g3 "$(awk 'BEGIN { for (i = 0; i < 100; i++) printf "  activity a%d() { task nothere; };\n", i }')" |
    shape g3-many-diagnostics genom3
{ printf '\357\273\277/* \001\002\033[31m \177 */\n'; g3 '  const string s = "\t\033";'; } | shape g3-bom-control genom3

# Dialect (targets parse and check). Nesting within and past the 64-level guard.
dialect='component c { category: default; lang: C; }\n'
for n in 60 70; do
    printf "${dialect}const long k = %s1%s;\n" "$(rep '(' $n)" "$(rep ')' $n)" |
        shape "dialect-parens-$n" parse check
    printf "${dialect}ids d { %slong x; %s}\n" "$(rep 'struct s { ' $n)" "$(rep '} f; ' $n)" |
        shape "dialect-structs-$n" parse check
done
printf "${dialect}const long k = %s1;\n" "$(rep '1+' 2000)" | shape dialect-flat-2000 parse check
printf "${dialect}const long k = %s1%s;\n" "$(rep '1+(' 600)" "$(rep ')' 600)" |
    shape dialect-nested-600 parse check
printf "${dialect}const long k = 1 << 70;\nconst long l = 256 >> 4 >> 2;\nconst short s = 70000;\nconst octet o = 300;\nconst long x = 999999999999999999999999999999999999999999;\nids d { sequence<sequence<long>> a; }\n" |
    shape dialect-numbers parse check
# Durations over one day.
printf "${dialect}thread t { priority: 0; period: 90000s; }\nservice s {\n  thread: t;\n  max-time: 5000000000000000001ns;\n  start codel { exec: f(); max-time: 86401s; next: ; }\n}\n" |
    shape dialect-max-time parse check
printf "${dialect}thread t { priority: 0; period: 5000000000000000001ns; }\nservice s {\n  thread: t;\n  start codel { exec: f(); max-time: 18446744073709551615ns; next: ; }\n}\n" |
    shape dialect-period parse check
# A long line, control characters and a byte-order mark.
printf "${dialect}ids d { double %s; }\n" "$(rep 'x' 3000)" | shape dialect-long-line parse check
printf '\357\273\277/* \001\033[2J\177 */'"${dialect}"'ids d { double x := 0.0 "\t\033"; }\n' |
    shape dialect-bom-control parse check

# WCET files (target wcet): the tests' files, valid lines for the fuzz
# target's component, and hostile lines.
mkdir -p "$here/corpus/wcet"
find "$root/tests/fixtures" -name '*.wcet' |
    while read -r f; do
        sum=$(cksum < "$f" | cut -d' ' -f1)
        cp "$f" "$here/corpus/wcet/seed-$sum"
    done
valid='t.start 1ms\nt.main 2ms\nt.stop 1ms\ngo.start 3ms\ngo.exec 2.5ms\nset.validate 400us\nset.codel 1ms\n'
printf "# every codel of the fuzz component\n$valid" | shape wcet-valid wcet
printf "t.main 9ms\ngo.start 15ms\ngo.exec 15ms\nset.codel 5ms\n" | shape wcet-overrun wcet
printf "t.main 11ms\n" | shape wcet-codel-overrun wcet
printf "t.start 1ms\nt.start 2ms\ngo.exec 1ms # first\ngo.exec 1ms\n" | shape wcet-duplicates wcet
printf '\357\273\277t.start 1ms\n\357\273\277t.main 1ms\n' | shape wcet-bom wcet
printf 't.start 5000000000000000001ns\nt.main 18446744073709551615ns\nt.stop 18446744073709551616ns\ngo.start 86400s\ngo.exec 86401s\nset.codel 99999999999999999999999999999999999999999s\n' |
    shape wcet-huge wcet
printf 't.start 1\000ms\nt.main\0001ms\n\000\n' | shape wcet-nul wcet
printf 't.start 0.0000000001ms\nt.main 1.5ns\nt.stop .5ms\ngo.start 1.ms\ngo.exec .ms\nset.codel 1e3ms\nset.validate -1ms\n' |
    shape wcet-fractions wcet
printf 'nothere.start 1ms\ngo.strat 1ms\nset.cod 1ms\nt.mian 1ms\nnodot 1ms\nt.start 1 ms\nt.start\n t.main 1ms extra words\n...\n.start 1ms\nt. 1ms\n' |
    shape wcet-malformed wcet
printf 't.start 1ms\r\nt.main 1ms\r\n\tgo.start\t1ms\v\n# %s\nset.codel 1ms' "$(rep 'x' 3000)" |
    shape wcet-whitespace wcet

for t in parse check genom3 generated wcet; do
    echo "$t: $(ls "$here/corpus/$t" | wc -l) seed files"
done
