#!/usr/bin/env bash
# The contact time step against the sample's scatter (see bench/time_step_scatter.py).
exec /usr/bin/python3 "$(dirname "${BASH_SOURCE[0]}")/time_step_scatter.py" "$@"
