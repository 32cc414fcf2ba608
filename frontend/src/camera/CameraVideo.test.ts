import { describe, expect, it } from "vitest";
import { closeCamera } from "./CameraVideo";

/** A video and a stream of two tracks that write down what is done to them, in order. */
function camera(): { video: HTMLVideoElement; stream: MediaStream; done: string[] } {
  const done: string[] = [];
  const track = (kind: string) => ({ stop: () => done.push(`stop ${kind}`) });
  const stream = { getTracks: () => [track("video"), track("audio")] } as unknown as MediaStream;
  let source: MediaStream | null = stream;
  const video = {
    pause: () => done.push("pause"),
    get srcObject() {
      return source;
    },
    set srcObject(value: MediaStream | null) {
      done.push(value ? "attach" : "detach");
      source = value;
    },
  } as unknown as HTMLVideoElement;
  return { video, stream, done };
}

describe("closeCamera", () => {
  it("lets the video go of the stream before its tracks stop", () => {
    const { video, stream, done } = camera();
    closeCamera(video, stream);
    expect(done).toEqual(["pause", "detach", "stop video", "stop audio"]);
    expect(video.srcObject).toBeNull();
  });

  it("stops the tracks of a stream no video showed, and a video without one is left alone", () => {
    const { video, stream, done } = camera();
    video.srcObject = null;
    done.length = 0;
    closeCamera(video, stream);
    expect(done).toEqual(["stop video", "stop audio"]);
    closeCamera(null, null);
    expect(done).toHaveLength(2);
  });
});
