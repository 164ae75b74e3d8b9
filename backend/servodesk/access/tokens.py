"""Access tokens: `SERVODESK_TOKENS="engineer=…,operator=…,viewer=…"` or a file with one
`role=token` (or `user:role=token`) per line. Pure: parsing and constant-time lookup."""

from __future__ import annotations

import hashlib
import hmac
from dataclasses import dataclass
from pathlib import Path

from servodesk.access.actor import Role

MIN_TOKEN_LENGTH = 12  # short tokens fall to guessing even behind the login rate limit


class TokenConfigError(ValueError):
    """The token configuration cannot be used; the message says where and why."""


@dataclass(frozen=True)
class Credential:
    user: str
    role: Role
    digest: bytes  # sha256 of the token: the token itself is not kept after start-up


def _digest(token: str) -> bytes:
    return hashlib.sha256(token.encode()).digest()


def parse_entry(text: str, where: str) -> Credential:
    """`role=token` or `user:role=token`."""
    name, sep, token = text.partition("=")
    if not sep:
        raise TokenConfigError(f"{where}: expected role=token or user:role=token")
    user, colon, role_text = name.strip().rpartition(":")
    try:
        role = Role.parse(role_text)
    except ValueError as error:
        raise TokenConfigError(f"{where}: {error}") from None
    token = token.strip()
    if len(token) < MIN_TOKEN_LENGTH:
        raise TokenConfigError(
            f"{where}: the {role.label} token is shorter than {MIN_TOKEN_LENGTH} characters; "
            "use a long random one (python3 -c 'import secrets; print(secrets.token_urlsafe())')"
        )
    user = user.strip() if colon else role.label
    if not user:
        raise TokenConfigError(f"{where}: empty user name before ':'")
    return Credential(user=user, role=role, digest=_digest(token))


class TokenTable:
    def __init__(self, credentials: list[Credential]) -> None:
        digests = [c.digest for c in credentials]
        if len(set(digests)) != len(digests):
            raise TokenConfigError("the same token is given twice: each user needs their own")
        self._credentials = credentials

    @property
    def configured(self) -> bool:
        return bool(self._credentials)

    def __len__(self) -> int:
        return len(self._credentials)

    def lookup(self, token: str) -> Credential | None:
        """The credential this token belongs to. Every entry is compared, each in constant
        time, so the answer's timing does not tell how close a guess was or which entry."""
        digest = _digest(token)
        found: Credential | None = None
        for credential in self._credentials:
            if hmac.compare_digest(credential.digest, digest):
                found = credential
        return found

    @classmethod
    def load(cls, tokens: str | None, tokens_file: Path | None) -> TokenTable:
        credentials: list[Credential] = []
        if tokens:
            for number, part in enumerate(tokens.split(","), start=1):
                if part.strip():
                    credentials.append(parse_entry(part, f"SERVODESK_TOKENS entry {number}"))
        if tokens_file is not None:
            try:
                lines = tokens_file.read_text(encoding="utf-8").splitlines()
            except (OSError, UnicodeDecodeError) as error:
                raise TokenConfigError(
                    f"cannot read the tokens file {tokens_file}: {error}"
                ) from None
            for number, line in enumerate(lines, start=1):
                text = line.strip()
                if text and not text.startswith("#"):
                    credentials.append(parse_entry(text, f"{tokens_file}:{number}"))
        return cls(credentials)
