import { describe, expect, it } from "vitest";
import { codeFrom, codeGroups } from "./joinCode";
import { CODE_DIGITS } from "./limits";
import { parseRoute } from "./routes";

describe("join codes", () => {
  it("are read from what was typed, with or without spaces", () => {
    expect(codeFrom("48291375")).toBe("48291375");
    expect(codeFrom(" 4829 1375 ")).toBe("48291375");
    expect(codeFrom("4829-1375")).toBe("48291375");
  });

  it("are refused when a digit is missing, extra or not a digit", () => {
    expect(codeFrom("4829 137")).toBeNull();
    expect(codeFrom("4829 13750")).toBeNull();
    expect(codeFrom("4829 137a")).toBeNull();
    expect(codeFrom("")).toBeNull();
  });

  it("are shown in two groups of four", () => {
    expect(codeGroups("48291375")).toEqual(["4829", "1375"]);
    expect(codeGroups("48291375").join("")).toHaveLength(CODE_DIGITS);
  });

  it("open the join screen from the join link", () => {
    expect(parseRoute("/join/48291375")).toEqual({ name: "join", code: "48291375" });
    expect(parseRoute("/join/48291375/")).toEqual({ name: "join", code: "48291375" });
    expect(parseRoute("/join/482913")).toEqual({ name: "start" });
  });
});
