"""
For mereo's own tests only.
"""
from __future__ import annotations
__all__: list[str] = ['register_test_nodes']
def register_test_nodes() -> None:
    """
    Registers the test-only node kinds identity, checksum and fail_on_frame (idempotent); they are added by kind name (Graph.add('checksum', ...)), not listed in mereo.nodes.
    """
