"""Signed bundles: an appliance given its owner's public key runs only what that owner's compiler signed.

A bundle's ``manifest.json`` lists every member with its SHA-256, so hashes alone stop damage, not an attacker:
whoever can replace a model can rewrite the manifest's hashes too. An Ed25519 signature over the manifest's exact
bytes (``manifest.sig``, base64) closes that: it cannot be remade without the private key. Ed25519 through the
``cryptography`` package (well kept, constant-time, what OpenSSH and OpenSSL use); keys are PEM files, made with
e.g. ``openssl genpkey -algorithm ed25519 -out key.pem`` and ``openssl pkey -in key.pem -pubout -out key.pub``.
"""

from __future__ import annotations

import base64
import binascii
from pathlib import Path

from vc.errors import InputError

SIGNATURE = "manifest.sig"


def _crypto():
    try:
        from cryptography.exceptions import InvalidSignature
        from cryptography.hazmat.primitives import serialization
        from cryptography.hazmat.primitives.asymmetric import ed25519
    except ImportError:  # the runtime's 'signatures' extra installs it; numpy + onnxruntime alone cannot check them
        raise InputError(None, "public_key", "checking or making signatures needs the 'cryptography' package: "
                                             "install the runtime's 'signatures' extra "
                                             "(pip install 'visual-compiler-runtime[signatures]')") from None
    return serialization, ed25519, InvalidSignature


def sign_manifest(manifest: bytes, private_key: Path) -> bytes:
    """``manifest.sig``'s content: the base64 Ed25519 signature of ``manifest`` with the PEM ``private_key``."""
    serialization, ed25519, _ = _crypto()
    try:
        key = serialization.load_pem_private_key(Path(private_key).read_bytes(), password=None)
    except FileNotFoundError:
        raise InputError(private_key, "", "signing key not found") from None
    except (ValueError, TypeError) as error:
        raise InputError(private_key, "", f"not an unencrypted PEM private key ({error})") from None
    if not isinstance(key, ed25519.Ed25519PrivateKey):
        raise InputError(private_key, "", "not an Ed25519 key (make one with: openssl genpkey -algorithm ed25519)")
    return base64.b64encode(key.sign(manifest)) + b"\n"


def verify_manifest(manifest: bytes, signature: bytes | None, public_key: Path | bytes, bundle: Path) -> None:
    """Refuse (InputError) unless ``signature`` is ``public_key``'s signature of ``manifest``."""
    serialization, ed25519, invalid_signature = _crypto()
    try:
        pem = public_key if isinstance(public_key, bytes) else Path(public_key).read_bytes()
        key = serialization.load_pem_public_key(pem)
    except FileNotFoundError:
        raise InputError(public_key, "", "public key not found") from None
    except (ValueError, TypeError) as error:
        raise InputError(None if isinstance(public_key, bytes) else public_key, "",
                         f"not a PEM public key ({error})") from None
    if not isinstance(key, ed25519.Ed25519PublicKey):
        raise InputError(None if isinstance(public_key, bytes) else public_key, "", "not an Ed25519 public key")
    if signature is None:
        raise InputError(bundle, SIGNATURE, "the bundle is not signed, and a public key was given: refused")
    try:
        key.verify(base64.b64decode(signature.strip(), validate=True), manifest)
    except (invalid_signature, binascii.Error, ValueError):
        raise InputError(bundle, SIGNATURE, "the signature does not match the manifest (rewritten, or signed by "
                                            "another key): refused") from None
