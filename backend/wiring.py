"""Every service of one process, built once from the settings when the app starts."""

from __future__ import annotations

from dataclasses import dataclass

from sqlalchemy import Engine

from backend.clock import Clock
from backend.eventstream.listener import ChangeListener
from backend.eventstream.log import EventLog
from backend.eventstream.notifier import Notifier
from backend.eventstream.presence import Presence
from backend.eventstream.stream import EventStreams
from backend.pairing.repository import Pairings
from backend.pairing.service import PairingService
from backend.photos.repository import Photos
from backend.photos.service import PhotoService
from backend.sessions.state import StateService
from backend.settings import Settings
from backend.storage.database import Database
from backend.storage.erase import Eraser
from backend.taps.answers import AnswerService
from backend.taps.pictures import PictureService
from backend.taps.repository import TapStore
from backend.taps.service import TapService
from backend.taps.shown import needed_after_photo


@dataclass
class Services:
    database: Database
    notifier: Notifier
    eraser: Eraser
    pairing: PairingService
    photos: PhotoService
    answers: AnswerService
    taps: TapService
    pictures: PictureService
    state: StateService
    streams: EventStreams
    listener: ChangeListener | None

    def healthy(self) -> bool:
        """The database answers, and (PostgreSQL) changes from other replicas are heard."""
        listening = self.listener is None or self.listener.listening
        return self.database.answers() and listening


def build(engine: Engine, settings: Settings, clock: Clock) -> Services:
    database, notifier = Database(engine), Notifier()
    eraser = Eraser(database, settings.erase_interval_seconds)
    pairing = PairingService(
        database=database,
        store=Pairings(database, eraser),
        settings=settings,
        notifier=notifier,
        clock=clock,
    )
    photo_store = Photos(database)
    photos = PhotoService(
        photos=photo_store,
        settings=settings,
        notifier=notifier,
        clock=clock,
        needed=needed_after_photo,
    )
    tap_store = TapStore(database)
    answers = AnswerService(
        database=database, taps=tap_store, settings=settings, notifier=notifier, clock=clock
    )
    taps = TapService(
        answers=answers, taps=tap_store, settings=settings, notifier=notifier, clock=clock
    )
    pictures = PictureService(
        answers=answers, photos=photo_store, photo_service=photos, settings=settings
    )
    streams = EventStreams(
        log=EventLog(database),
        presence=Presence(database),
        notifier=notifier,
        clock=clock,
        keepalive_seconds=settings.keepalive_seconds,
        poll_seconds=settings.event_poll_seconds,
    )
    # Other replicas' changes reach this process's streams by LISTEN/NOTIFY on PostgreSQL.
    listener = (
        ChangeListener(engine.url, notifier.notify, notifier.notify_all)
        if database.postgresql
        else None
    )
    return Services(
        database=database,
        notifier=notifier,
        eraser=eraser,
        pairing=pairing,
        photos=photos,
        answers=answers,
        taps=taps,
        pictures=pictures,
        state=StateService(answers, taps, pairing, settings, clock),
        streams=streams,
        listener=listener,
    )
