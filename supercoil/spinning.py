"""Placeholder: being implemented (see the issue tracker)."""


def twist_spinning(*args, **kwargs):
    raise NotImplementedError("twist_spinning is not implemented yet")
