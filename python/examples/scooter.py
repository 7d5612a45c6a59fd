# %% [markdown]
# # The scooter ride, every planar estimator
#
# A Jupyter-style script (cells marked `# %%`: open it in VS Code or Jupyter with
# jupytext, or run it whole with `python scooter.py`). It simulates the 60 s scooter ride
# of the paper (the pendulum on the floorboard, engine running), runs every estimator on
# it and plots each one's error against the true tilt, one panel per family.

# %%
import os

import matplotlib

if not os.environ.get("DISPLAY") and "ipykernel" not in os.environ.get("_", ""):
    matplotlib.use("Agg")  # no screen: write the figure to a file
import matplotlib.pyplot as plt
import numpy as np

import pendtilt

DURATION = float(os.environ.get("PENDTILT_EXAMPLE_DURATION", "60"))  # s
FIGURE = os.environ.get("PENDTILT_EXAMPLE_FIGURE", "scooter_errors.png")

# %% Simulate: the log (t, phi, gyro, ax, ay and the true tilt theta) and its rig file.
ride = pendtilt.simulate("scooter", duration=DURATION, seed=1)
df = ride.to_pandas()
df.head()

# %% Estimate: every estimator the columns feed, with the rig simulate wrote.
est = pendtilt.estimate(df, rig=ride.rig)
print(est.error_table())

# %% Plot the error of each estimator [deg], one panel per family.
families = {}
for row in pendtilt.catalogue():
    if row["name"] in est.names:
        families.setdefault(row["family"], []).append(row["name"])
fig, axes = plt.subplots(len(families), 1, sharex=True, figsize=(9, 2.2 * len(families)))
t = est["t"]
for ax, (family, names) in zip(np.atleast_1d(axes), families.items()):
    for name in names:
        error = np.degrees(est[name] - est["theta"])
        ax.plot(t, error, lw=0.6, label=f"{name} (RMS {np.degrees(est.rms[name]):.3f})")
    ax.set_title(family, fontsize=9, loc="left")
    ax.set_ylabel("error [deg]")
    ax.set_ylim(-5, 5)
    ax.legend(fontsize=7, loc="upper right", ncol=2)
np.atleast_1d(axes)[-1].set_xlabel("t [s]")
fig.tight_layout()
fig.savefig(FIGURE, dpi=120)
print(f"figure: {FIGURE}")
