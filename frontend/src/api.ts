/**
 * The REST API, called through openapi-fetch with the types generated from the server's
 * OpenAPI schema (generated/openapi.ts; the app's names for them: types.ts). Every refusal
 * is {"error": {"code", "message"}}; the message is a sentence for the person, shown as it
 * is.
 */

import createClient, { type Client } from "openapi-fetch";
import type { paths } from "./generated/openapi";
import type {
  CreatedSession,
  Credentials,
  Joined,
  LandmarkSuggestion,
  PhotoFields,
  PhotoStored,
  Reanchored,
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
    /** The solver's reason, for its refusals (`frame_not_matched`, ...). */
    readonly reason: string | null = null,
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
  const error = (body as { error?: { code?: unknown; message?: unknown; reason?: unknown } } | null)?.error;
  if (error && typeof error.code === "string" && typeof error.message === "string") {
    return new ApiError(status, error.code, error.message, typeof error.reason === "string" ? error.reason : null);
  }
  const fallback = status >= 500 ? "The server had a problem; try again." : `Refused (${status}).`;
  return new ApiError(status, "http_" + status, fallback);
}

/**
 * The API, typed by the app's own OpenAPI schema (openapi-fetch over generated/openapi.ts):
 * a path, its parameters and its body are checked against the schema at compile time.
 * `token` goes as the Bearer header; no read is ever answered from the browser's cache (a
 * session's state is what it is now). Made per call: openapi-fetch takes the page's fetch
 * and Request when a client is made, and the unit tests put theirs in place per test.
 */
function client(token?: string): Client<paths> {
  return createClient<paths>({
    // Absolute: openapi-fetch builds a Request, which outside a page (the unit tests) needs it.
    baseUrl: location.origin,
    cache: "no-store",
    headers: token ? { Authorization: `Bearer ${token}` } : {},
  });
}

/**
 * What a call answered, or its ApiError. Kept as our own because openapi-fetch returns a
 * refusal as a value ({error, response}) and lets a lost connection throw whatever fetch
 * throws, while the app's callers (the tap saver, the upload's retries, the state fetch)
 * act on a thrown ApiError: its server's stable `code`, `retryable`, `sessionEnded`. A body
 * that is not the API's JSON (a captive portal's page) is no answer either.
 */
async function answerOf<T>(call: Promise<{ data?: T; error?: unknown; response: Response }>): Promise<T> {
  let answer: Awaited<typeof call>;
  try {
    answer = await call;
  } catch {
    throw new ApiError(0, "network", NO_CONNECTION);
  }
  if (!answer.response.ok) throw errorFrom(answer.response.status, answer.error);
  return answer.data as T;
}

export function createSession(): Promise<CreatedSession> {
  return answerOf(client().POST("/api/sessions"));
}

export function joinSession(code: string): Promise<Joined> {
  return answerOf(client().POST("/api/sessions/join", { body: { code } }));
}

export function fetchState({ session_id, token }: Credentials): Promise<SessionState> {
  return answerOf(client(token).GET("/api/sessions/{session_id}", { params: { path: { session_id } } }));
}

export function putTaps({ session_id, token }: Credentials, taps: Taps): Promise<SessionState> {
  return answerOf(client(token).PUT("/api/sessions/{session_id}/taps", { params: { path: { session_id } }, body: taps }));
}

/** Where landmark `id`, tapped by the other phone, probably is in `role`'s photo. */
export function fetchSuggestion({ session_id, token }: Credentials, role: Role, id: number): Promise<LandmarkSuggestion> {
  return answerOf(
    client(token).GET("/api/sessions/{session_id}/landmarks/{role}/{landmark_id}/suggestion", {
      params: { path: { session_id, role, landmark_id: id } },
    }),
  );
}

export async function deleteSession({ session_id, token }: Credentials): Promise<void> {
  await answerOf(client(token).DELETE("/api/sessions/{session_id}", { params: { path: { session_id } } }));
}

function withToken(path: string, token: string, extra: Record<string, string> = {}): string {
  const query = new URLSearchParams({ token, ...extra });
  return `${path}?${query.toString()}`;
}

// <img> and EventSource cannot send headers: these take ?token=.

export function photoUrl({ session_id, token }: Credentials, role: Role, key: string): string {
  return withToken(`/api/sessions/${session_id}/photo/${role}`, token, { v: key });
}

export function cropUrl({ session_id, token }: Credentials, role: Role, id: number, key: string): string {
  return withToken(`/api/sessions/${session_id}/landmarks/${role}/${id}/crop`, token, { v: key });
}

export function eventsUrl({ session_id, token }: Credentials): string {
  return withToken(`/api/sessions/${session_id}/events`, token);
}

/**
 * PUT the photo, with the lens its original's EXIF told and what the in-app camera read at
 * the shutter (`fields`: form fields beside the photo; a list goes as the same field once per
 * item, in order), with XMLHttpRequest, which (unlike fetch, and so openapi-fetch) reports upload
 * progress: `onProgress` gets 0..1. Hence our own request here; its refusals are the same
 * ApiErrors.
 */
export function uploadPhoto(
  { session_id, token }: Credentials,
  body: Blob,
  name: string,
  fields: PhotoFields,
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
    for (const [field, value] of Object.entries(fields)) {
      const values: unknown[] = Array.isArray(value) ? value : [value];
      for (const item of values) if (item !== undefined && item !== null) form.append(field, String(item));
    }
    request.send(form);
  });
}

/**
 * What the server read from a live frame matched to this phone's photo (re-anchoring, "Show
 * me"; the type is the server's, types.ts): `rotation` takes a direction in the photo's
 * camera frame into the frame's (x right, y down, z out of the lens), `frame_focal_px` is
 * the frame's focal length in px of the frame as sent. Checked before use: a rotation that
 * is not 3 x 3 numbers would draw the marker anywhere.
 */
function isReanchored(body: unknown): body is Reanchored {
  const r = body as Partial<Reanchored> | null;
  const rotation = r?.rotation;
  return (
    Array.isArray(rotation) &&
    rotation.length === 3 &&
    rotation.every((row) => Array.isArray(row) && row.length === 3 && row.every(Number.isFinite)) &&
    typeof r?.frame_focal_px === "number" &&
    r.frame_focal_px > 0
  );
}

/**
 * POST one small frame of the live view (a JPEG) to be matched to this phone's own photo.
 * The frame's focal length is left to the server to measure (the phone does not know its
 * video's; `frame_focal_px`, for a caller that does, would be taken as known). Refused with
 * 422 `no_solution` (reason `frame_not_matched`) when the frame does not match.
 */
export async function reanchor({ session_id, token }: Credentials, frame: Blob): Promise<Reanchored> {
  const form = new FormData();
  form.append("frame", frame, "frame.jpeg");
  let response: Response;
  try {
    response = await fetch(`/api/sessions/${session_id}/reanchor`, {
      method: "POST",
      headers: { Authorization: `Bearer ${token}` },
      body: form,
      cache: "no-store",
    });
  } catch {
    throw new ApiError(0, "network", NO_CONNECTION);
  }
  let body: unknown = null;
  try {
    body = await response.json();
  } catch {
    body = null;
  }
  if (!response.ok) throw errorFrom(response.status, body);
  if (!isReanchored(body)) throw new ApiError(response.status, "bad_answer", "The server's answer could not be read; try again.");
  return body;
}
