import { describe, expect, it } from "vitest";
import python from "../../shared_solver/drawing/palette.py?raw";
import {
  FRIEND_COLOUR,
  LANDMARK_COLOURS,
  SUSPECT_COLOUR,
  landmarkColour,
} from "./palette";

function pythonColours(name: string): string[] {
  const block = new RegExp(`${name}[^=]*=\\s*\\(([^)]*)\\)`, "s").exec(python);
  return block?.[1] ? [...block[1].matchAll(/"(#[0-9a-fA-F]{6})"/g)].map((m) => m[1] ?? "") : [];
}

function pythonColour(name: string): string {
  return new RegExp(`${name}\\s*=\\s*"(#[0-9a-fA-F]{6})"`).exec(python)?.[1] ?? "";
}

describe("the palette", () => {
  it("is the server's 12 landmark colours, in order", () => {
    expect(LANDMARK_COLOURS).toHaveLength(12);
    expect([...LANDMARK_COLOURS]).toEqual(pythonColours("LANDMARK_COLOURS_HEX"));
  });

  it("has the server's friend yellow and suspect red", () => {
    expect(FRIEND_COLOUR).toBe("#ffd400");
    expect(SUSPECT_COLOUR).toBe("#ff1f1f");
    expect(FRIEND_COLOUR).toBe(pythonColour("FRIEND_COLOUR_HEX"));
    expect(SUSPECT_COLOUR).toBe(pythonColour("SUSPECT_COLOUR_HEX"));
  });

  it("paints landmark k with colour (k - 1) mod 12", () => {
    expect(landmarkColour(1)).toBe("#3cb44b");
    expect(landmarkColour(3)).toBe("#ff8c1a");
    expect(landmarkColour(12)).toBe("#8fa8ff");
    expect(landmarkColour(13)).toBe("#3cb44b");
    expect(landmarkColour(27)).toBe(landmarkColour(3));
  });
});
