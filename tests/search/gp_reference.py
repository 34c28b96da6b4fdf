"""scikit-learn reference for tests/search/gaussian_process_test.cpp.

Reads a JSON problem (x, y, prior_mean, theta, x_test, bounds, restarts) from the file named by
argv[1]; prints {"mean", "std", "lml", "fitted_lml", "fitted_theta"} as JSON. The prior mean is
subtracted by hand because scikit-learn's GP has a zero prior mean. Exits 3 when scikit-learn is
missing so the test can skip.
"""
import json
import sys
import warnings

warnings.filterwarnings("ignore")  # bound warnings are expected on random data

try:
    import numpy as np
    from sklearn.gaussian_process import GaussianProcessRegressor
    from sklearn.gaussian_process.kernels import ConstantKernel, Matern, WhiteKernel
except ImportError as error:
    print(f"scikit-learn unavailable: {error}")
    sys.exit(3)

p = json.load(open(sys.argv[1]))
x = np.array(p["x"])
y = np.array(p["y"]) - p["prior_mean"]
x_test = np.array(p["x_test"])
theta = np.exp(np.array(p["theta"]))
b = p["bounds"]  # log bounds: signal, length, noise


def kernel(t):
    return (ConstantKernel(t[0], (np.exp(b["signal"][0]), np.exp(b["signal"][1])))
            * Matern(length_scale=t[1:-1], length_scale_bounds=(np.exp(b["length"][0]), np.exp(b["length"][1])), nu=2.5)
            + WhiteKernel(t[-1], (np.exp(b["noise"][0]), np.exp(b["noise"][1]))))


fixed = GaussianProcessRegressor(kernel(theta), alpha=0.0, optimizer=None).fit(x, y)
mean, std = fixed.predict(x_test, return_std=True)
fitted = GaussianProcessRegressor(kernel(theta), alpha=0.0, n_restarts_optimizer=p["restarts"], random_state=0).fit(x, y)
print(json.dumps({
    "mean": (mean + p["prior_mean"]).tolist(),
    "std": std.tolist(),
    "lml": float(fixed.log_marginal_likelihood_value_),
    "fitted_lml": float(fitted.log_marginal_likelihood_value_),
    "fitted_theta": fitted.kernel_.theta.tolist(),
}))
