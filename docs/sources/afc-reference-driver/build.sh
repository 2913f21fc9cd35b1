#!/bin/bash
# Builds build/afc_ref from the sim2cpp export copy in src-sim2cpp/ (single core, sequential).
set -e
cd "$(dirname "$0")/.."
S=src-sim2cpp/AbstractFuelControl_M1_grt_rtw
mkdir -p build && cd build
FL="-O2 -ffp-contract=off -fno-fast-math -Dprivate=public -I../$S"
for f in AbstractFuelControl_M1 AbstractFuelControl_M1_data rt_nonfinite rt_zcfcn rtGetNaN; do g++ -std=c++17 $FL -c ../$S/$f.cpp -o $f.o; done
gcc $FL -c ../$S/rt_logging.c -o rt_logging.o
g++ -std=c++17 $FL -c ../driver/afc_ref_main.cpp -o main.o
g++ *.o -o afc_ref -lm
