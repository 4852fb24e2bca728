"""``supercoil params NAME``: print a parameter set with units and sources."""

from __future__ import annotations


def register(sub):
    p = sub.add_parser("params", help="print a parameter set with units and sources")
    p.add_argument("name", nargs="?", help="bundled set name or path to a TOML file; "
                   "omit to list the bundled sets")
    p.set_defaults(func=run)


def run(args) -> int:
    from supercoil.parameters import available_parameter_sets, read_parameter_set

    if not args.name:
        print("\n".join(available_parameter_sets()))
        return 0
    print(read_parameter_set(args.name).describe())
    return 0
