"""The example problems shipped with the package: ``designer.example_problem("indoor-manual")``.

The files in ``designer/data/problems/`` are copies of the repository's ``problems/*.toml``
(``tests/problem/test_examples.py`` keeps them byte-equal), shipped as package data so that a notebook
or a script finds them from any working directory and from a non-editable install.
"""

from __future__ import annotations

from designer.errors import ProblemError
from designer.problem._core import Problem
from designer.problem._loader import problem_from_toml, shipped_folder, example_names

__all__ = ["example_names", "example_problem", "example_text"]


def example_text(name: str) -> str:
    """The TOML text of the shipped example problem ``name`` (docs/problem-file.md describes the keys).

    Raises
    ------
    ProblemError
        One line naming the unknown name and listing the shipped ones.
    """
    names = example_names()
    if name not in names:
        raise ProblemError(
            f"example_problem: name = {name!r}: no such example problem; the shipped ones are {', '.join(names)}"
        )
    return str((shipped_folder() / f"{name}.toml").read_text(encoding="utf-8"))


def example_problem(name: str = "indoor-manual") -> Problem:
    """A shipped example problem, validated, the same as loading ``problems/<name>.toml`` of the repository.

    Works from any working directory (the TOML is package data), which is what a notebook needs.
    ``"indoor-manual"`` is the default problem: a manual chair, 178 N per caster, 1/2 in door sills,
    no shimmy up to V_target = 2.5 m/s (Eq. 7, risk-bounded by default).

    Parameters
    ----------
    name
        One of :func:`example_names`: ``"indoor-manual"``, ``"indoor-manual-robust"``,
        ``"catalog-retrofit"``, ``"paper-invacare"``, ``"powered-chair"``, ``"sports-court"``.

    Returns
    -------
    Problem
        With ``source = None`` (it was not read from a file on disk).

    Raises
    ------
    ProblemError
        One line naming the unknown name and listing the shipped ones.

    Examples
    --------
    >>> import designer
    >>> designer.example_problem("indoor-manual").target_speed
    2.5
    """
    return problem_from_toml(example_text(name), source=None, default_name=name)
