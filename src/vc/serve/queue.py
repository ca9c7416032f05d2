"""Events waiting for the broker, on disk: a bounded first-in-first-out queue in one SQLite file.

Why SQLite (the standard library's): every push is one transaction, so a power cut or a SIGKILL leaves the queue
as it was before or after an event, never half-written, and a restart finds every event not yet acknowledged by
the broker, in order. An event leaves the queue only when the broker has acknowledged it (MQTT QoS 1, PUBACK).

The queue is bounded: beyond ``limit`` events the oldest are dropped, logged and counted (a broker gone for days
must not fill the appliance's disk).
"""

from __future__ import annotations

import logging
import sqlite3
import threading
from pathlib import Path
from typing import NamedTuple

from vc.errors import InputError

log = logging.getLogger("vc.serve")


class QueuedEvent(NamedTuple):
    sequence: int  # the queue's order, increasing over the file's whole life
    topic: str
    payload: str


class EventQueue:
    """The queue in ``path`` (created if absent, resumed if present), at most ``limit`` events."""

    def __init__(self, path: Path, limit: int) -> None:
        self.path, self.limit = Path(path), limit
        self.dropped = 0  # since this process started
        self._lock = threading.Lock()
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._db = sqlite3.connect(self.path, check_same_thread=False, isolation_level=None)
            self._db.execute("PRAGMA journal_mode=WAL")
            self._db.execute("PRAGMA synchronous=FULL")  # an acknowledged push survives a power cut
            self._db.execute("CREATE TABLE IF NOT EXISTS events (sequence INTEGER PRIMARY KEY AUTOINCREMENT, "
                             "topic TEXT NOT NULL, payload TEXT NOT NULL)")
            self._depth = self._db.execute("SELECT COUNT(*) FROM events").fetchone()[0]
        except sqlite3.DatabaseError as error:
            raise InputError(self.path, "", f"not a usable event queue ({error})") from None
        if self._depth:
            log.info("event queue %s: %d event(s) from before, delivered first", self.path, self._depth)

    @property
    def depth(self) -> int:
        return self._depth

    def push(self, topic: str, payload: str) -> int:
        """Append one event; the oldest go beyond the limit. Returns how many were dropped to make room."""
        with self._lock:
            with self._db:
                self._db.execute("BEGIN IMMEDIATE")
                self._db.execute("INSERT INTO events (topic, payload) VALUES (?, ?)", (topic, payload))
                excess = self._depth + 1 - self.limit
                if excess > 0:
                    self._db.execute("DELETE FROM events WHERE sequence IN "
                                     "(SELECT sequence FROM events ORDER BY sequence LIMIT ?)", (excess,))
            dropped = max(excess, 0)
            self._depth += 1 - dropped
            self.dropped += dropped
        if dropped:
            log.warning("event queue %s full (%d events): the oldest %d dropped (%d since start)", self.path,
                        self.limit, dropped, self.dropped)
        return dropped

    def oldest(self, count: int, after: int = 0) -> list[QueuedEvent]:
        """Up to ``count`` events in order, from the first after sequence ``after``."""
        with self._lock:
            rows = self._db.execute("SELECT sequence, topic, payload FROM events WHERE sequence > ? "
                                    "ORDER BY sequence LIMIT ?", (after, count)).fetchall()
        return [QueuedEvent(*row) for row in rows]

    def remove(self, sequence: int) -> None:
        """An event the broker acknowledged."""
        with self._lock:
            removed = self._db.execute("DELETE FROM events WHERE sequence = ?", (sequence,)).rowcount
            self._depth -= removed

    def close(self) -> None:
        with self._lock:
            self._db.execute("PRAGMA wal_checkpoint(TRUNCATE)")
            self._db.close()
