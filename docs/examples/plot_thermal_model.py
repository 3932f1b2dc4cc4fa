"""
A temperature-dependent noise model
===================================

[TS]'s procedure: static logs at several chamber temperatures, each analysed for angle random
walk, bias instability and an AR(1) drift model, then every parameter interpolated in
temperature. Here the simulated sensor's ARW grows linearly with temperature.
"""

import matplotlib.pyplot as plt
import numpy as np

from gyrobias import noise, thermal

fs = 100.0
temperatures = [-30.0, -10.0, 10.0, 30.0, 50.0]
true_arw = {t: (0.15 + 0.002 * (t + 30)) / 60 for t in temperatures}  # deg/√s
logs = {
    t: noise.simulate(60_000, fs, arw=true_arw[t], bias_instability=3 / 3600, seed=int(t) + 40)
    for t in temperatures
}
model = thermal.build_temperature_model(logs, fs=fs, units="deg/s", method="pchip")
print(model)

grid = np.linspace(-30, 50, 161)
fig, ax = plt.subplots(figsize=(7, 4))
ax.plot(temperatures, [60 * model("arw", t) for t in temperatures], "o", label="per-log read-off")
ax.plot(grid, [60 * model("arw", t) for t in grid], label="PCHIP model")
ax.plot(temperatures, [60 * true_arw[t] for t in temperatures], "k:", label="simulated")
ax.set_xlabel("temperature [°C]")
ax.set_ylabel("ARW [deg/√h]")
ax.legend()
ax.set_title("Angle random walk against temperature")
fig.tight_layout()
