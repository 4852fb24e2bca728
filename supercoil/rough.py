"""Placeholder: being implemented (see the issue tracker)."""


def rough_helix(*args, **kwargs):
    raise NotImplementedError("rough_helix is not implemented yet")
