/**
 * The REST API (its types: generated from the server's OpenAPI schema, types.ts). Every
 * refusal is {"error": {"code", "message"}}; the message is a sentence for the person,
 * shown as it is.
 */

import type {
  CreatedSession,
  Credentials,
  Joined,
  LandmarkSuggestion,
  LensFields,
  PhotoStored,
  Role,
  SessionState,
  Taps,
} from "./types";

/** A refusal from the server, or (status 0, code "network") no answer at all. */
export class ApiError extends Error {
  constructor(
    readonly status: number,
    readonly code: string,
    message: string,
  ) {
    super(message);
    this.name = "ApiError";
  }

  /** Worth trying again: no answer, or the server (or a proxy) was briefly unwell. */
  get retryable(): boolean {
    return this.status === 0 || this.status === 408 || this.status === 429 || this.status >= 500;
  }

  /** The session is gone for this phone: ended, deleted or timed out. */
  get sessionEnded(): boolean {
    return this.status === 401 || (this.status === 404 && this.code === "session_not_found");
  }
}

export const NO_CONNECTION = "No connection to the server. Trying again...";

export function isRetryable(error: unknown): boolean {
  return error instanceof ApiError && error.retryable;
}

/** The ApiError in a response body (or a plain one when the body is not the usual shape). */
export function errorFrom(status: number, body: unknown): ApiError {
  const error = (body as { error?: { code?: unknown; message?: unknown } } | null)?.error;
  if (error && typeof error.code === "string" && typeof error.message === "string") {
    return new ApiError(status, error.code, error.message);
  }
  const fallback = status >= 500 ? "The server had a problem; try again." : `Refused (${status}).`;
  return new ApiError(status, "http_" + status, fallback);
}

async function call<T>(path: string, init: RequestInit = {}, token?: string): Promise<T> {
  const headers = new Headers(init.headers);
  if (token) headers.set("Authorization", `Bearer ${token}`);
  if (init.body && typeof init.body === "string") headers.set("Content-Type", "application/json");
  let response: Response;
  try {
    response = await fetch(path, { ...init, headers, cache: "no-store" });
  } catch {
    throw new ApiError(0, "network", NO_CONNECTION);
  }
  if (response.status === 204) return undefined as T;
  let body: unknown = null;
  try {
    body = await response.json();
  } catch {
    body = null;
  }
  if (!response.ok) throw errorFrom(response.status, body);
  return body as T;
}

export function createSession(): Promise<CreatedSession> {
  return call("/api/sessions", { method: "POST" });
}

export function joinSession(code: string): Promise<Joined> {
  return call("/api/sessions/join", { method: "POST", body: JSON.stringify({ code }) });
}

export function fetchState({ session_id, token }: Credentials): Promise<SessionState> {
  return call(`/api/sessions/${session_id}`, {}, token);
}

export function putTaps({ session_id, token }: Credentials, taps: Taps): Promise<SessionState> {
  return call(`/api/sessions/${session_id}/taps`, { method: "PUT", body: JSON.stringify(taps) }, token);
}

/** Where landmark `id`, tapped by the other phone, probably is in `role`'s photo. */
export function fetchSuggestion({ session_id, token }: Credentials, role: Role, id: number): Promise<LandmarkSuggestion> {
  return call(`/api/sessions/${session_id}/landmarks/${role}/${id}/suggestion`, {}, token);
}

export function deleteSession({ session_id, token }: Credentials): Promise<void> {
  return call(`/api/sessions/${session_id}`, { method: "DELETE" }, token);
}

function withToken(path: string, token: string, extra: Record<string, string> = {}): string {
  const query = new URLSearchParams({ token, ...extra });
  return `${path}?${query.toString()}`;
}

// <img> and EventSource cannot send headers: these take ?token=.

export function photoUrl({ session_id, token }: Credentials, role: Role, key: string): string {
  return withToken(`/api/sessions/${session_id}/photo/${role}`, token, { v: key });
}

export function overlayUrl({ session_id, token }: Credentials, role: Role, version: number): string {
  return withToken(`/api/sessions/${session_id}/overlay/${role}`, token, { v: String(version) });
}

export function cropUrl({ session_id, token }: Credentials, role: Role, id: number, key: string): string {
  return withToken(`/api/sessions/${session_id}/landmarks/${role}/${id}/crop`, token, { v: key });
}

export function eventsUrl({ session_id, token }: Credentials): string {
  return withToken(`/api/sessions/${session_id}/events`, token);
}

/**
 * PUT the photo, with the lens its original's EXIF told (`lens`: form fields beside the
 * photo), with XMLHttpRequest, which (unlike fetch) reports upload progress: `onProgress`
 * gets 0..1.
 */
export function uploadPhoto(
  { session_id, token }: Credentials,
  body: Blob,
  name: string,
  lens: LensFields,
  onProgress: (fraction: number) => void,
): Promise<PhotoStored> {
  return new Promise((resolve, reject) => {
    const request = new XMLHttpRequest();
    request.open("PUT", `/api/sessions/${session_id}/photo`);
    request.setRequestHeader("Authorization", `Bearer ${token}`);
    request.responseType = "text";
    request.timeout = 120_000;
    request.upload.onprogress = (event) => {
      if (event.lengthComputable && event.total > 0) onProgress(event.loaded / event.total);
    };
    const noAnswer = (): void => reject(new ApiError(0, "network", NO_CONNECTION));
    request.onerror = noAnswer;
    request.ontimeout = noAnswer;
    request.onabort = noAnswer;
    request.onload = () => {
      let answer: unknown = null;
      try {
        answer = JSON.parse(request.responseText);
      } catch {
        answer = null;
      }
      if (request.status >= 200 && request.status < 300) {
        onProgress(1);
        resolve(answer as PhotoStored);
      } else {
        reject(errorFrom(request.status, answer));
      }
    };
    const form = new FormData();
    form.append("photo", body, name);
    for (const [field, value] of Object.entries(lens)) {
      if (value !== undefined && value !== null) form.append(field, String(value));
    }
    request.send(form);
  });
}
