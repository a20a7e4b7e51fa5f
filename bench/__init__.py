"""Benchmarks: ``python -m bench [NAME ...]`` prints one JSON object per figure.

Each figure: ``{"name", "value", "unit", "goal", "higher_is_better", "detail"}``; ``name`` is
``<group>.<figure>_<unit>`` or ``<group>.<figure>``. Values are medians over repeated runs, and a
figure compared with a peer or floor has that peer measured in the same run.
"""
