from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast
from uuid import UUID

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.job_state_enum import JobStateEnum, check_job_state_enum

T = TypeVar("T", bound="Job")


@_attrs_define
class Job:
    """The base of every model serializer of the API.

    Attributes:
        id (UUID):
        url (str):
        fleet (str):
        kind (str):
        title (str): what the job does, in words
        arguments (Any):
        created_by (str):
        state (JobStateEnum): * `pending` - Pending
            * `running` - Running
            * `succeeded` - Succeeded
            * `failed` - Failed
            * `cancelled` - Cancelled
        progress (int):
        message (str):
        result (Any): summary of what the job produced
        result_url (str):
        error (str):
        attempts (int):
        worker (str): host:pid of the process running the job
        heartbeat (datetime.datetime | None): last sign of life of a worker's run (in-process runs send none)
        interruption (str): why an earlier attempt ended unfinished (e.g. its worker was lost)
        cancel_requested (datetime.datetime | None): when a cancel of the running job was asked (its run stops at its
            next step)
        cancel_unavailable (str): why POST .../cancel/ would be refused now ('' when the job can be cancelled)
        retry_unavailable (str): why POST .../retry/ would be refused now ('' when the job can be retried)
        waiting_notice (str): a pending job no worker has picked up for a minute: how long, and what is ahead of it (''
            else)
        retry_of (None | UUID): the job this one runs again, with the same arguments
        created (datetime.datetime):
        queued (datetime.datetime | None): when the job's message was last sent to the workers' queue
        started (datetime.datetime | None):
        finished (datetime.datetime | None):
        duration (float | None):
    """

    id: UUID
    url: str
    fleet: str
    kind: str
    title: str
    arguments: Any
    created_by: str
    state: JobStateEnum
    progress: int
    message: str
    result: Any
    result_url: str
    error: str
    attempts: int
    worker: str
    heartbeat: datetime.datetime | None
    interruption: str
    cancel_requested: datetime.datetime | None
    cancel_unavailable: str
    retry_unavailable: str
    waiting_notice: str
    retry_of: UUID | None
    created: datetime.datetime
    queued: datetime.datetime | None
    started: datetime.datetime | None
    finished: datetime.datetime | None
    duration: float | None
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = str(self.id)

        url = self.url

        fleet = self.fleet

        kind = self.kind

        title = self.title

        arguments = self.arguments

        created_by = self.created_by

        state: str = self.state

        progress = self.progress

        message = self.message

        result = self.result

        result_url = self.result_url

        error = self.error

        attempts = self.attempts

        worker = self.worker

        heartbeat: str | None
        heartbeat = self.heartbeat.isoformat() if isinstance(self.heartbeat, datetime.datetime) else self.heartbeat

        interruption = self.interruption

        cancel_requested: str | None
        if isinstance(self.cancel_requested, datetime.datetime):
            cancel_requested = self.cancel_requested.isoformat()
        else:
            cancel_requested = self.cancel_requested

        cancel_unavailable = self.cancel_unavailable

        retry_unavailable = self.retry_unavailable

        waiting_notice = self.waiting_notice

        retry_of: str | None
        retry_of = str(self.retry_of) if isinstance(self.retry_of, UUID) else self.retry_of

        created = self.created.isoformat()

        queued: str | None
        queued = self.queued.isoformat() if isinstance(self.queued, datetime.datetime) else self.queued

        started: str | None
        started = self.started.isoformat() if isinstance(self.started, datetime.datetime) else self.started

        finished: str | None
        finished = self.finished.isoformat() if isinstance(self.finished, datetime.datetime) else self.finished

        duration: float | None
        duration = self.duration

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "url": url,
                "fleet": fleet,
                "kind": kind,
                "title": title,
                "arguments": arguments,
                "created_by": created_by,
                "state": state,
                "progress": progress,
                "message": message,
                "result": result,
                "result_url": result_url,
                "error": error,
                "attempts": attempts,
                "worker": worker,
                "heartbeat": heartbeat,
                "interruption": interruption,
                "cancel_requested": cancel_requested,
                "cancel_unavailable": cancel_unavailable,
                "retry_unavailable": retry_unavailable,
                "waiting_notice": waiting_notice,
                "retry_of": retry_of,
                "created": created,
                "queued": queued,
                "started": started,
                "finished": finished,
                "duration": duration,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = UUID(d.pop("id"))

        url = d.pop("url")

        fleet = d.pop("fleet")

        kind = d.pop("kind")

        title = d.pop("title")

        arguments = d.pop("arguments")

        created_by = d.pop("created_by")

        state = check_job_state_enum(d.pop("state"))

        progress = d.pop("progress")

        message = d.pop("message")

        result = d.pop("result")

        result_url = d.pop("result_url")

        error = d.pop("error")

        attempts = d.pop("attempts")

        worker = d.pop("worker")

        def _parse_heartbeat(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                heartbeat_type_0 = datetime.datetime.fromisoformat(data)

                return heartbeat_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        heartbeat = _parse_heartbeat(d.pop("heartbeat"))

        interruption = d.pop("interruption")

        def _parse_cancel_requested(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                cancel_requested_type_0 = datetime.datetime.fromisoformat(data)

                return cancel_requested_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        cancel_requested = _parse_cancel_requested(d.pop("cancel_requested"))

        cancel_unavailable = d.pop("cancel_unavailable")

        retry_unavailable = d.pop("retry_unavailable")

        waiting_notice = d.pop("waiting_notice")

        def _parse_retry_of(data: object) -> UUID | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                retry_of_type_0 = UUID(data)

                return retry_of_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(UUID | None, data)

        retry_of = _parse_retry_of(d.pop("retry_of"))

        created = datetime.datetime.fromisoformat(d.pop("created"))

        def _parse_queued(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                queued_type_0 = datetime.datetime.fromisoformat(data)

                return queued_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        queued = _parse_queued(d.pop("queued"))

        def _parse_started(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                started_type_0 = datetime.datetime.fromisoformat(data)

                return started_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        started = _parse_started(d.pop("started"))

        def _parse_finished(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                finished_type_0 = datetime.datetime.fromisoformat(data)

                return finished_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        finished = _parse_finished(d.pop("finished"))

        def _parse_duration(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        duration = _parse_duration(d.pop("duration"))

        job = cls(
            id=id,
            url=url,
            fleet=fleet,
            kind=kind,
            title=title,
            arguments=arguments,
            created_by=created_by,
            state=state,
            progress=progress,
            message=message,
            result=result,
            result_url=result_url,
            error=error,
            attempts=attempts,
            worker=worker,
            heartbeat=heartbeat,
            interruption=interruption,
            cancel_requested=cancel_requested,
            cancel_unavailable=cancel_unavailable,
            retry_unavailable=retry_unavailable,
            waiting_notice=waiting_notice,
            retry_of=retry_of,
            created=created,
            queued=queued,
            started=started,
            finished=finished,
            duration=duration,
        )

        job.additional_properties = d
        return job

    @property
    def additional_keys(self) -> list[str]:
        return list(self.additional_properties.keys())

    def __getitem__(self, key: str) -> Any:
        return self.additional_properties[key]

    def __setitem__(self, key: str, value: Any) -> None:
        self.additional_properties[key] = value

    def __delitem__(self, key: str) -> None:
        del self.additional_properties[key]

    def __contains__(self, key: str) -> bool:
        return key in self.additional_properties
