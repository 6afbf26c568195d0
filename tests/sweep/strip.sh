#!/usr/bin/env bash
# Prints a sweep's results.csv without the columns that measure the machine (rtf, wall_s):
# what must be identical for any -j and any number of MPI ranks.
awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) drop[i] = ($i == "rtf" || $i == "wall_s") }
         { line = ""; for (i = 1; i <= NF; ++i) if (!drop[i]) line = line (line == "" ? "" : ",") $i; print line }' "$1"
