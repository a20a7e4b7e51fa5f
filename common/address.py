"""Network addresses as users write them on the command line."""

from __future__ import annotations


def parse_address(text: str, default_port: int) -> tuple[str, int]:
    """``HOST:PORT``, ``:PORT`` or ``PORT`` (host 127.0.0.1: loopback unless asked otherwise).

    Raises
    ------
    ValueError
        For a port that is not a number in 0..65535.
    """
    host, _, port = text.rpartition(":") if ":" in text else ("", "", text)
    try:
        number = int(port) if port else default_port
    except ValueError:
        raise ValueError(f"expected HOST:PORT, got {text!r}") from None
    if not 0 <= number <= 65535:
        raise ValueError(f"port must be 0..65535, got {number}")
    return (host.strip("[]") or "127.0.0.1", number)
