import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import type { TapSet } from "./landmarks";
import type { Credentials, SensorFields } from "./types";
import { localPhoto, scaleTaps, sendPhoto } from "./upload";

const TAPS: TapSet = {
  landmarks: [{ id: 1, x: 100, y: 50, sigma: 2 }],
  friend: { x: 10, y: 20, sigma: null },
  friend_line: null,
};

describe("the phone's own copy of its photo", () => {
  it("is shown at the size it is sent, pending until the server has it", () => {
    const body = new Blob(["jpeg"], { type: "image/jpeg" });
    const shown = localPhoto({ body, size: { width: 2560, height: 1920 }, name: "photo.jpg" }, "k1");
    expect(shown).toMatchObject({ size: { width: 2560, height: 1920 }, key: "k1", pending: true });
    expect(shown?.local).toMatch(/^blob:/);
  });

  it("is not shown when its size is unknown (the original file goes as it is)", () => {
    const body = new Blob(["heic"]);
    expect(localPhoto({ body, size: null, name: "photo.heic" }, "k2")).toBeNull();
  });
});

describe("taps moved to the stored photo's size", () => {
  it("keeps taps when the sizes match", () => {
    const size = { width: 640, height: 480 };
    expect(scaleTaps(TAPS, size, size)).toBe(TAPS);
  });

  it("scales points and sigmas", () => {
    const half = scaleTaps(TAPS, { width: 640, height: 480 }, { width: 320, height: 240 });
    expect(half.landmarks[0]).toEqual({ id: 1, x: 50, y: 25, sigma: 1 });
    expect(half.friend).toEqual({ x: 5, y: 10, sigma: null });
  });

  it("keeps a line through the same points", () => {
    // x + y - 100 = 0 through (100, 0) and (0, 100), normalised.
    const r = Math.SQRT1_2;
    const taps: TapSet = { ...TAPS, friend: null, friend_line: { a: r, b: r, c: -100 * r, sigma: 2 } };
    const line = scaleTaps(taps, { width: 200, height: 200 }, { width: 100, height: 50 }).friend_line;
    expect(line).not.toBeNull();
    if (!line) return;
    expect(Math.hypot(line.a, line.b)).toBeCloseTo(1);
    for (const [x, y] of [[50, 0], [0, 25]] as const) expect(line.a * x + line.b * y + line.c).toBeCloseTo(0);
  });
});

describe("the photo's form fields", () => {
  const PHONE: Credentials = { session_id: "s1", token: "t1", role: "starter" };
  const PREPARED = { body: new Blob(["jpeg"], { type: "image/jpeg" }), size: { width: 4, height: 3 }, name: "photo.jpg" };
  const SENSORS: SensorFields = {
    gravity: [0.1, 0.98, -0.2],
    gravity_sigma_deg: 1.3,
    heading: 131.25,
    heading_sigma_deg: 15,
  };
  let sent: FormData[];
  /** The status of each request in turn (then 200). */
  let statuses: number[];

  /** XMLHttpRequest as uploadPhoto reads it (what it only sets is left out): the form is
   * kept, the answer comes at once. */
  class FakeRequest {
    status = 0;
    responseText = "";
    upload: { onprogress: ((event: ProgressEvent) => void) | null } = { onprogress: null };
    onload: (() => void) | null = null;
    open(): void {}
    setRequestHeader(): void {}
    send(form: FormData): void {
      sent.push(form);
      this.status = statuses.shift() ?? 200;
      const ok = this.status === 200;
      this.responseText = JSON.stringify(
        ok ? { width: 4, height: 3 } : { error: { code: "invalid_request", message: "No such lens." } },
      );
      queueMicrotask(() => this.onload?.());
    }
  }

  beforeEach(() => {
    sent = [];
    statuses = [];
    vi.stubGlobal("XMLHttpRequest", FakeRequest);
  });

  afterEach(() => vi.unstubAllGlobals());

  it("sends down as the same field three times, x, y, z, with its sigma, the heading and its sigma, beside the lens", async () => {
    await sendPhoto(PHONE, PREPARED, { focal_35mm: 26 }, SENSORS, () => {});
    const [form] = sent;
    expect(form?.getAll("gravity")).toEqual(["0.1", "0.98", "-0.2"]);
    expect(form?.get("gravity_sigma_deg")).toBe("1.3");
    expect(form?.getAll("heading")).toEqual(["131.25"]);
    expect(form?.get("heading_sigma_deg")).toBe("15");
    expect(form?.get("focal_35mm")).toBe("26");
    expect(form?.get("photo")).toBeInstanceOf(Blob);
  });

  it("sends no sensor fields for a photo of the phone's camera app or the gallery", async () => {
    await sendPhoto(PHONE, PREPARED, { focal_35mm: 26 }, null, () => {});
    expect(sent).toHaveLength(1);
    expect(sent[0]?.has("gravity")).toBe(false);
    expect(sent[0]?.has("gravity_sigma_deg")).toBe(false);
    expect(sent[0]?.has("heading")).toBe(false);
  });

  it("refused, sends the photo again without the sensors, then without the lens", async () => {
    statuses = [422, 422];
    await sendPhoto(PHONE, PREPARED, { focal_35mm: 26 }, SENSORS, () => {});
    const fields = (form: FormData): boolean[] => ["gravity", "heading", "focal_35mm", "photo"].map((f) => form.has(f));
    expect(sent.map(fields)).toEqual([
      [true, true, true, true],
      [false, false, true, true],
      [false, false, false, true],
    ]);
  });

  it("refused with nothing left to leave out, says so", async () => {
    statuses = [422];
    await expect(sendPhoto(PHONE, PREPARED, {}, null, () => {})).rejects.toMatchObject({ status: 422 });
    expect(sent).toHaveLength(1);
  });
});
