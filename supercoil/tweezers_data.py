"""Placeholder: being implemented (see the issue tracker)."""


def read_tweezers_csv(*args, **kwargs):
    raise NotImplementedError("read_tweezers_csv is not implemented yet")
