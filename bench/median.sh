# Shared by the bench scripts (source it): the medians that summarise rounds.
# median: the median of the numbers on standard input, "-" when there are
# none; for an even count the mean of the middle two, to 4 significant digits.
median() { sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) print "-"; else if (NR % 2) print v[(NR + 1) / 2]; else printf "%.4g\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# median_of X...: the median of the arguments.
median_of() { (($#)) && printf '%s\n' "$@" | median || echo "-"; }
