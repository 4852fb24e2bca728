"""Placeholder: being implemented (see the issue tracker)."""


def hat_curve(*args, **kwargs):
    raise NotImplementedError("hat_curve is not implemented yet")
