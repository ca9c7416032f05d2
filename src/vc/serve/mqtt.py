"""The events, from the on-disk queue to an MQTT broker, in order, each until the broker acknowledges it.

1. A paho-mqtt client keeps the connection (its own network thread; it reconnects by itself, waiting 1 s and up
   to ``reconnect_max_s`` between tries).
2. A sender thread publishes the queue's oldest events at QoS 1, at most ``max_in_flight`` unacknowledged at once.
3. An acknowledgement (PUBACK) removes the event from the queue. Until then it stays on disk: a broker outage, a
   restart or a power cut loses nothing that was queued.
4. After a lost connection, paho sends again (flagged DUP) what was in flight; the sender publishes nothing new
   until those are acknowledged, so events reach the broker in the queue's order.

Delivery is therefore at least once: an event whose acknowledgement was lost with the connection (or with the
process, before a restart) can reach the broker twice. Its ``id`` says so to a subscriber.
"""

from __future__ import annotations

import logging
import socket
import threading

import paho.mqtt.client as paho

from vc.serve.config import MqttSettings
from vc.serve.queue import EventQueue

log = logging.getLogger("vc.serve")


class Publisher:
    """Delivers ``queue`` to the broker of ``settings``; ``on_published(count)`` tells the metrics."""

    def __init__(self, settings: MqttSettings, queue: EventQueue, reconnect_max_s: float = 10.0,
                 on_published=lambda count: None) -> None:
        self.settings, self.queue, self.on_published = settings, queue, on_published
        client_id = settings.client_id or f"vc-serve-{socket.gethostname()}"
        self.client = paho.Client(paho.CallbackAPIVersion.VERSION2, client_id=client_id, clean_session=False)
        if settings.username is not None:
            self.client.username_pw_set(settings.username, settings.password)
        self.client.max_inflight_messages_set(settings.max_in_flight)
        self.client.reconnect_delay_set(1, int(max(1, reconnect_max_s)))
        self.client.on_connect = self._connected
        self.client.on_disconnect = self._disconnected
        self.client.on_publish = self._acknowledged
        self.connected = False
        self.published = 0
        self._in_flight: dict[int, int] = {}  # message id -> queue sequence
        self._early: set[int] = set()  # message ids acknowledged before they were recorded as in flight
        self._last_sent = 0  # the queue sequence of the last event handed to paho
        self._wake = threading.Condition()
        self._stopping = False
        self._resending = False  # after a reconnect, until what was in flight is acknowledged
        self._thread = threading.Thread(target=self._send, name="mqtt-send", daemon=True)

    def start(self) -> None:
        self.client.connect_async(self.settings.host, self.settings.port, self.settings.keepalive_s)
        self.client.loop_start()
        self._thread.start()

    def notify(self) -> None:
        """New events are in the queue."""
        with self._wake:
            self._wake.notify()

    @property
    def in_flight(self) -> int:
        with self._wake:
            return len(self._in_flight)

    def stop(self, drain_s: float = 2.0) -> None:
        """Deliver what is queued for up to ``drain_s`` while connected (the last events, a track's end among them,
        reach the broker now rather than at the next start), then stop sending; what is not acknowledged by then stays
        queued."""
        with self._wake:
            self._wake.wait_for(lambda: self.queue.depth == 0 or not self.connected, timeout=drain_s)
            self._stopping = True
            self._wake.notify_all()
        self._thread.join(timeout=5)
        self.client.disconnect()
        self.client.loop_stop()

    # paho's callbacks (its network thread)
    def _connected(self, client, userdata, flags, reason_code, properties) -> None:
        if reason_code.is_failure:
            log.warning("mqtt: %s:%d refused the connection: %s", self.settings.host, self.settings.port, reason_code)
            return
        log.info("mqtt: connected to %s:%d", self.settings.host, self.settings.port)
        with self._wake:
            self.connected = True
            self._resending = bool(self._in_flight)
            self._wake.notify_all()

    def _disconnected(self, client, userdata, flags, reason_code, properties) -> None:
        with self._wake:
            if self.connected and not self._stopping:
                log.warning("mqtt: lost %s:%d (%s); events wait in %s", self.settings.host, self.settings.port,
                            reason_code, self.queue.path)
            self.connected = False

    def _acknowledged(self, client, userdata, mid, reason_code, properties) -> None:
        # paho calls this holding its outgoing-message lock: take no lock that a thread inside publish() holds
        with self._wake:
            sequence = self._in_flight.pop(mid, None)
            if sequence is None:  # acknowledged before the sender recorded it
                self._early.add(mid)
                return
            self._done(sequence)

    def _done(self, sequence: int) -> None:
        """An acknowledged event leaves the queue (under ``_wake``)."""
        self.queue.remove(sequence)
        self.published += 1
        if not self._in_flight:
            self._resending = False
        self._wake.notify_all()
        self.on_published(1)

    # the sender thread
    def _ready(self) -> bool:
        return self._stopping or (self.connected and not self._resending
                                  and len(self._in_flight) < self.settings.max_in_flight
                                  and self.queue.depth > len(self._in_flight))

    def _send(self) -> None:
        while True:
            with self._wake:
                self._wake.wait_for(self._ready, timeout=1.0)
                if self._stopping:
                    return
                if not self._ready():
                    continue
                batch = self.queue.oldest(self.settings.max_in_flight - len(self._in_flight), after=self._last_sent)
            for event in batch:  # outside the lock: paho's publish() takes the lock its callbacks run under
                info = self.client.publish(event.topic, event.payload, qos=1)
                if info.rc not in (paho.MQTT_ERR_SUCCESS, paho.MQTT_ERR_NO_CONN):
                    log.warning("mqtt: publish refused (%s); retried", paho.error_string(info.rc))
                    break
                # paho keeps a QoS 1 message it could not send yet and sends it on connecting: in flight too
                with self._wake:
                    self._last_sent = event.sequence
                    if info.mid in self._early:
                        self._early.discard(info.mid)
                        self._done(event.sequence)
                    else:
                        self._in_flight[info.mid] = event.sequence
