import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import { ApiError, deleteSession, fetchState, joinSession, putTaps, reanchor } from "./api";
import { IDENTITY } from "./live/orientation";
import type { Credentials } from "./types";

const PHONE: Credentials = { session_id: "s1", token: "t1", role: "joiner" };

describe("the API's calls", () => {
  let sent: Request[];
  let reply: () => Promise<Response>;

  beforeEach(() => {
    sent = [];
    reply = () => Promise.resolve(Response.json({ version: 3 }));
    vi.stubGlobal("location", { origin: "http://phone.test" });
    vi.stubGlobal("fetch", (request: Request) => {
      sent.push(request);
      return reply();
    });
  });

  afterEach(() => vi.unstubAllGlobals());

  it("sends the token, reads nothing from the cache, and fills the path from the schema's names", async () => {
    expect(await fetchState(PHONE)).toEqual({ version: 3 });
    const [request] = sent;
    expect(request?.method).toBe("GET");
    expect(request?.url).toBe("http://phone.test/api/sessions/s1");
    expect(request?.headers.get("Authorization")).toBe("Bearer t1");
    expect(request?.cache).toBe("no-store");
  });

  it("sends a body as JSON, and no token before the phone has one", async () => {
    await joinSession("12345678");
    await putTaps(PHONE, { landmarks: [], friend: null, friend_line: null });
    const [join, taps] = sent;
    expect(join?.headers.get("Authorization")).toBeNull();
    expect(join?.headers.get("Content-Type")).toBe("application/json");
    expect(await join?.json()).toEqual({ code: "12345678" });
    expect(taps?.method).toBe("PUT");
    expect(await taps?.json()).toEqual({ landmarks: [], friend: null, friend_line: null });
  });

  it("turns a refusal into an ApiError with the server's code and sentence", async () => {
    reply = () => Promise.resolve(Response.json({ error: { code: "session_not_found", message: "No such search." } }, { status: 404 }));
    const refusal = await fetchState(PHONE).catch((error: unknown) => error);
    expect(refusal).toBeInstanceOf(ApiError);
    expect(refusal).toMatchObject({ status: 404, code: "session_not_found", message: "No such search.", sessionEnded: true, retryable: false });
  });

  it("says a proxy's error page is the server's problem, worth another try", async () => {
    reply = () => Promise.resolve(new Response("<html>Bad gateway</html>", { status: 502 }));
    await expect(fetchState(PHONE)).rejects.toMatchObject({ status: 502, code: "http_502", retryable: true });
  });

  it("says no connection when no answer comes, or one that is not the API's (a captive portal)", async () => {
    reply = () => Promise.reject(new TypeError("Failed to fetch"));
    await expect(fetchState(PHONE)).rejects.toMatchObject({ status: 0, code: "network", retryable: true });
    reply = () => Promise.resolve(new Response("<html>Log in to the venue's Wi-Fi</html>", { status: 200 }));
    await expect(fetchState(PHONE)).rejects.toMatchObject({ status: 0, code: "network", retryable: true });
  });

  it("takes a deletion's empty answer as done", async () => {
    reply = () => Promise.resolve(new Response(null, { status: 204 }));
    await expect(deleteSession(PHONE)).resolves.toBeUndefined();
    expect(sent[0]?.method).toBe("DELETE");
  });
});

describe("re-anchoring (Show me)", () => {
  let sent: { url: string; init: RequestInit | undefined }[];
  let reply: () => Promise<Response>;
  const ROTATION = IDENTITY;

  beforeEach(() => {
    sent = [];
    reply = () => Promise.resolve(Response.json({ rotation: ROTATION, frame_focal_px: 800, inliers: 120, degrees: 0 }));
    vi.stubGlobal("fetch", (url: string, init?: RequestInit) => {
      sent.push({ url, init });
      return reply();
    });
  });

  afterEach(() => vi.unstubAllGlobals());

  it("posts the frame, with the token, for the server to measure its focal length", async () => {
    const answer = await reanchor(PHONE, new Blob(["jpeg"], { type: "image/jpeg" }));
    expect(answer).toMatchObject({ rotation: ROTATION, frame_focal_px: 800 });
    const [call] = sent;
    expect(call?.url).toBe("/api/sessions/s1/reanchor");
    expect(call?.init?.method).toBe("POST");
    expect((call?.init?.headers as Record<string, string>).Authorization).toBe("Bearer t1");
    const form = call?.init?.body as FormData;
    expect(form.get("frame")).toBeInstanceOf(Blob);
    expect(form.has("frame_focal_px")).toBe(false);
  });

  it("says a frame that did not match by its reason", async () => {
    const error = { code: "no_solution", reason: "frame_not_matched", message: "The frame does not match the photo." };
    reply = () => Promise.resolve(Response.json({ error }, { status: 422 }));
    await expect(reanchor(PHONE, new Blob(["jpeg"]))).rejects.toMatchObject({ status: 422, code: "no_solution", reason: "frame_not_matched" });
  });

  it("refuses an answer that is no rotation", async () => {
    reply = () => Promise.resolve(Response.json({ rotation: [[1, 0], [0, 1]], frame_focal_px: 800 }));
    await expect(reanchor(PHONE, new Blob(["jpeg"]))).rejects.toBeInstanceOf(ApiError);
  });
});
