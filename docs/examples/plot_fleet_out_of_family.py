"""
A fleet's out-of-family units
=============================

Twelve simulated units from an end-of-line test (3 axes, 10 minutes at 100 Hz each), one of
which has twice the angle random walk on its y axis. :func:`gyrobias.fleet.analyse` fits every
unit on Dask (here: the local threaded scheduler) and flags the unit whose robust z-score
exceeds 3.5.
"""

import numpy as np

from gyrobias import fleet, noise, plotting

fs, n, units = 100.0, 60_000, 12
rates = np.stack(
    [
        noise.simulate(n, fs, arw=0.2 / 60, bias_instability=3 / 3600, axes=3, seed=100 + u)
        for u in range(units)
    ]
)
rates[7, :, 1] += noise.simulate(n, fs, arw=0.35 / 60, seed=99)  # unit 7's y axis is noisier

table = fleet.analyse(rates, fs=fs, units="deg/s", axis_names=["x", "y", "z"], terms=("N", "B"))
print(
    table.loc[
        table.out_of_family, ["source", "axis", "N", "N_uncertainty", "N_z", "out_of_family_terms"]
    ]
)
print(fleet.summary(table)[["axis", "term", "median", "spread", "spread_real"]])
fig = plotting.plot_fleet(table, title="12 units, unit 7's y axis out of family")
