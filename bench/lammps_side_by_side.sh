#!/usr/bin/env bash
# The LAMMPS side by side (see bench/lammps_side_by_side.py for what runs).
exec /usr/bin/python3 "$(dirname "${BASH_SOURCE[0]}")/lammps_side_by_side.py" "$@"
