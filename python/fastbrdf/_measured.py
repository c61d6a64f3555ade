"""Placeholder: filled by its own change (issue 29)."""

from typing import List

__all__: List[str] = []
