"""Set-membership filters and their stochastic baselines."""

from .classical import classical_filter, first_inconsistency
from .consistency import Inconsistency, ModelInvalidatedError, ModelInvalidationWarning
from .interval import interval_filter
from .kalman import KalmanResult, kalman_filter, rts_smoother
from .oit import OITResult, oit_inspired_filter
from .oit_cz import oit_cz_filter
from .steps import predict, update

__all__ = ["classical_filter", "predict", "update", "interval_filter", "kalman_filter", "rts_smoother",
           "KalmanResult", "oit_inspired_filter", "oit_cz_filter", "OITResult", "first_inconsistency",
           "Inconsistency", "ModelInvalidationWarning", "ModelInvalidatedError"]
