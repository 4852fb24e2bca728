"""Placeholder: being implemented (see the issue tracker)."""


def plectoneme_equilibrium(*args, **kwargs):
    raise NotImplementedError("plectoneme_equilibrium is not implemented yet")


def effective_twist_rigidity(*args, **kwargs):
    raise NotImplementedError("effective_twist_rigidity is not implemented yet")


def extension_factor(*args, **kwargs):
    raise NotImplementedError("extension_factor is not implemented yet")
