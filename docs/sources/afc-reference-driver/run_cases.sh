#!/bin/bash
# Generates reference traces with the sim2cpp export (see traces/README.md). Single core, sequential.
set -e
cd "$(dirname "$0")/.."
B=build/afc_ref
H=${H:-0.000025}
OUT=${OUT:-traces}
mkdir -p $OUT
run() { name=$1; eng=$2; shift 2; $B 0.9 60 $H $eng 5 "$@" > $OUT/$name.csv 2> $OUT/$name.log; }
run a_p0_n1000          1000 0
run b_p30_n1000         1000 30
run c_afc29_n950        950  5 50 10 45 3 60 20 0 55 8
run d_afc33_n900        900  61.2 81.2 61.2 81.2 61.2 81.2 61.2 81.2 61.2 81.2
run e_afc27_n1000       1000 0 0 0 60 0 60 0 60 0 60
run f_p61.2_n1100       1100 61.2
run g1_mixed_n1050      1050 40 10 61.1 0 35 20 50 5 61.1 30
run g2_alt0_61.1_n900   900  0 61.1 0 61.1 0 61.1 0 61.1 0 61.1
run g3_mixed_n1100      1100 8.8 45 25 61 2 33 58 12 41 19
run g4_afc33_n1100      1100 81.2 61.2 81.2 61.2 81.2 61.2 81.2 61.2 81.2 61.2
