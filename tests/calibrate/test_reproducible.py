"""A calibration is the same to the bit whatever the BLAS thread count of the process
that runs it (a campaign stores its results by content: two runs of one campaign must
store one model)."""

import numpy as np
from airwake.calibrate import calibrate
from airwake.heli import load_spec
from threadpoolctl import threadpool_limits


def test_the_fit_does_not_depend_on_the_callers_blas_threads(still_air_flight):
    # a multi-threaded BLAS sums in an order set by its thread count, and least squares
    # with a finite-difference Jacobian follows the last bits (2e-4 apart in a fitted
    # parameter on such a flight when the fit ran on the caller's threads)
    fits = []
    for threads in (1, 2):
        with threadpool_limits(threads, user_api="blas"):
            res = calibrate(still_air_flight, model="table52", max_nfev=6, max_windows=8)
        fits.append(res.model.parameter_vector())
    assert not np.array_equal(fits[0], load_spec("table52").parameter_vector())
    np.testing.assert_array_equal(fits[0], fits[1])
