"""Lowest layer: exact predicates, flat data structures, spatial sorting, errors.

Nothing in ``core`` imports from any other meshwright sub-package.
"""
