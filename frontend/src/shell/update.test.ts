import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import { holdsUnsent } from "./busy";
import { register, reloadIfBuildGone } from "./update";

/** A service worker as the page sees it: its state, and what the page told it. */
class FakeWorker extends EventTarget {
  readonly messages: unknown[] = [];
  constructor(public state: ServiceWorkerState) {
    super();
  }
  postMessage(message: unknown): void {
    this.messages.push(message);
  }
  become(state: ServiceWorkerState): void {
    this.state = state;
    this.dispatchEvent(new Event("statechange"));
  }
}

class FakeRegistration extends EventTarget {
  active: FakeWorker | null = null;
  waiting: FakeWorker | null = null;
  installing: FakeWorker | null = null;
  update = vi.fn(() => Promise.resolve());
  /** A new build's worker starts installing. */
  found(worker: FakeWorker): void {
    this.installing = worker;
    this.dispatchEvent(new Event("updatefound"));
  }
}

class FakeContainer extends EventTarget {
  constructor(
    public controller: FakeWorker | null,
    readonly registration: FakeRegistration,
  ) {
    super();
  }
  register = vi.fn(() => Promise.resolve(this.registration));
  /** `worker` now controls the page. */
  controlledBy(worker: FakeWorker): void {
    this.controller = worker;
    this.dispatchEvent(new Event("controllerchange"));
  }
}

async function started(controller: FakeWorker | null): Promise<{ container: FakeContainer; reload: ReturnType<typeof vi.fn> }> {
  const container = new FakeContainer(controller, new FakeRegistration());
  container.registration.active = controller;
  const reload = vi.fn();
  await register(container as unknown as ServiceWorkerContainer, reload);
  return { container, reload };
}

afterEach(() => {
  vi.useRealTimers();
  vi.unstubAllGlobals();
});

describe("moving the page to a new build", () => {
  beforeEach(() => {
    vi.stubGlobal("document", Object.assign(new EventTarget(), { visibilityState: "visible" }));
  });

  it("does not reload a first visit that the first worker claims, even when told twice", async () => {
    const { container, reload } = await started(null);
    const first = new FakeWorker("activated");
    container.controlledBy(first);
    container.controlledBy(first);
    expect(reload).not.toHaveBeenCalled();
  });

  it("reloads a page a worker served when another tab moves to a new build", async () => {
    const { container, reload } = await started(new FakeWorker("activated"));
    container.controlledBy(new FakeWorker("activated"));
    expect(reload).toHaveBeenCalledTimes(1);
  });

  it("asks an installed new build to take over, then reloads once", async () => {
    const old = new FakeWorker("activated");
    const { container, reload } = await started(old);
    const next = new FakeWorker("installing");
    container.registration.found(next);
    expect(next.messages).toEqual([]);
    next.become("installed");
    expect(next.messages).toEqual([{ type: "SKIP_WAITING" }]);
    container.controlledBy(next);
    container.controlledBy(next);
    expect(reload).toHaveBeenCalledTimes(1);
  });

  it("takes the first install for no update, whenever it says it is installed", async () => {
    const { container, reload } = await started(null);
    const first = new FakeWorker("installing");
    container.registration.found(first);
    // WebKitGTK: the first worker claimed the page before its "installed" reached it.
    container.registration.active = first;
    container.controlledBy(first);
    first.become("installed");
    expect(first.messages).toEqual([]);
    expect(reload).not.toHaveBeenCalled();
  });

  it("reloads a first-visit page that a new build replaces later", async () => {
    const { container, reload } = await started(null);
    const first = new FakeWorker("activated");
    container.registration.active = first;
    container.controlledBy(first);
    const next = new FakeWorker("installing");
    container.registration.found(next);
    next.become("installed");
    container.controlledBy(next);
    expect(reload).toHaveBeenCalledTimes(1);
  });

  it("takes a build that waits since the last visit", async () => {
    const registration = new FakeRegistration();
    registration.active = new FakeWorker("activated");
    registration.waiting = new FakeWorker("installed");
    const container = new FakeContainer(registration.active, registration);
    await register(container as unknown as ServiceWorkerContainer, vi.fn());
    expect(registration.waiting.messages).toEqual([{ type: "SKIP_WAITING" }]);
  });

  it("waits while the page holds a photo not sent yet", async () => {
    vi.useFakeTimers();
    let unsent = true;
    const release = holdsUnsent(() => unsent);
    try {
      const { container } = await started(new FakeWorker("activated"));
      const next = new FakeWorker("installing");
      container.registration.found(next);
      next.become("installed");
      vi.advanceTimersByTime(10_000);
      expect(next.messages).toEqual([]);
      unsent = false;
      vi.advanceTimersByTime(2_000);
      expect(next.messages).toEqual([{ type: "SKIP_WAITING" }]);
    } finally {
      release();
    }
  });

  it("leaves a browser that refuses workers as it was", async () => {
    const container = new FakeContainer(null, new FakeRegistration());
    container.register = vi.fn(() => Promise.reject(new Error("refused")));
    await expect(register(container as unknown as ServiceWorkerContainer, vi.fn())).resolves.toBeUndefined();
  });
});

describe("after a lazily loaded chunk failed", () => {
  const ENTRY = "/assets/index-AAAA.js";
  /** index.html as a server of the build whose entry is `entry` answers it. */
  const index = (entry: string): Response =>
    new Response(`<script type="module" crossorigin src="${entry}"></script>`, { status: 200 });
  /** The server, moved on to another build. */
  const moved = (): Promise<Response> => Promise.resolve(index("/assets/index-BBBB.js"));
  let reload: ReturnType<typeof vi.fn>;

  beforeEach(() => {
    reload = vi.fn();
    const stored = new Map<string, string>();
    vi.stubGlobal("document", {
      querySelector: () => ({ src: `https://buddy.example${ENTRY}` }),
    });
    vi.stubGlobal("location", { href: "https://buddy.example/s" });
    vi.stubGlobal("sessionStorage", {
      getItem: (key: string) => stored.get(key) ?? null,
      setItem: (key: string, value: string) => stored.set(key, value),
    });
  });

  it("stays with no signal: a reload would show the browser's error page", async () => {
    const offline = vi.fn(() => Promise.reject(new TypeError("Load failed")));
    await expect(reloadIfBuildGone(offline, reload)).resolves.toBe(false);
    expect(offline).toHaveBeenCalledTimes(1);
    expect(reload).not.toHaveBeenCalled();
  });

  it("stays when the server is still on this build, or answers with an error", async () => {
    await expect(reloadIfBuildGone(() => Promise.resolve(index(ENTRY)), reload)).resolves.toBe(false);
    const failing = (): Promise<Response> => Promise.resolve(new Response("", { status: 502 }));
    await expect(reloadIfBuildGone(failing, reload)).resolves.toBe(false);
    expect(reload).not.toHaveBeenCalled();
  });

  it("reloads once when the server is on another build, not again within 10 s", async () => {
    vi.useFakeTimers();
    await expect(reloadIfBuildGone(moved, reload)).resolves.toBe(true);
    vi.advanceTimersByTime(5_000);
    await expect(reloadIfBuildGone(moved, reload)).resolves.toBe(false);
    vi.advanceTimersByTime(6_000);
    await expect(reloadIfBuildGone(moved, reload)).resolves.toBe(true);
    expect(reload).toHaveBeenCalledTimes(2);
  });

  it("stays while the page holds a photo not sent yet", async () => {
    const release = holdsUnsent(() => true);
    try {
      const asked = vi.fn(moved);
      await expect(reloadIfBuildGone(asked, reload)).resolves.toBe(false);
      expect(asked).not.toHaveBeenCalled();
      expect(reload).not.toHaveBeenCalled();
    } finally {
      release();
    }
  });
});
