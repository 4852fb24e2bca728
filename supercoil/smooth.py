"""Placeholder: being implemented (see the issue tracker)."""


def smooth_helix(*args, **kwargs):
    raise NotImplementedError("smooth_helix is not implemented yet")
