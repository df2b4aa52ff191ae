"""The JSON attributes of a store: their hash (the store's identity) and their decoder."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from typing import Any

from rocking._json import json_default

__all__ = ["config_hash", "decode_attrs"]


def config_hash(obj: Any) -> str:
    """Short sha256 of the canonical JSON of ``obj`` (sorted keys, no blanks).

    Used as the identity of the result-affecting configuration of a store.
    """
    text = json.dumps(obj, sort_keys=True, separators=(",", ":"), default=json_default)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def decode_attrs(attrs: Mapping[str, Any]) -> dict[str, Any]:
    """Store attributes with their JSON-text values decoded (the one decoder of them).

    :func:`rocking.store.create_store` writes every attribute that is not a string as
    JSON text; plain strings (a title, a version) that are not JSON are kept as they are.
    """
    out = {}
    for k, v in attrs.items():
        try:
            out[k] = json.loads(v) if isinstance(v, str) else v
        except json.JSONDecodeError:
            out[k] = v
    return out

