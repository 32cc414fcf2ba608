import { describe, expect, it } from "vitest";
import { REDUCE_MOTION_QUERY, prefersReducedMotion } from "./motion";

describe("prefersReducedMotion", () => {
  it("asks the system's reduce-motion setting", () => {
    const asked: string[] = [];
    const media = (matches: boolean) => (query: string) => {
      asked.push(query);
      return { matches };
    };
    expect(prefersReducedMotion(media(true))).toBe(true);
    expect(prefersReducedMotion(media(false))).toBe(false);
    expect(asked).toEqual([REDUCE_MOTION_QUERY, REDUCE_MOTION_QUERY]);
  });

  it("is false where the page cannot ask", () => {
    expect(prefersReducedMotion(undefined)).toBe(false);
  });
});
