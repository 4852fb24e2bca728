"""Placeholder: being implemented (see the issue tracker)."""


def design_twist_schedule(*args, **kwargs):
    raise NotImplementedError("design_twist_schedule is not implemented yet")
