"""Placeholder: being implemented (see the issue tracker)."""


class FitResult:
    pass


def fit_hat_curves(*args, **kwargs):
    raise NotImplementedError("fit_hat_curves is not implemented yet")


def fit_many(*args, **kwargs):
    raise NotImplementedError("fit_many is not implemented yet")
