import { afterAll, describe, expect, it } from "vitest";
import { NOTHING, type AnswerView } from "../answer";
import { speak } from "../i18n";
import de from "../i18n/locales/de.json";
import en from "../i18n/locales/en.json";
import es from "../i18n/locales/es.json";
import fr from "../i18n/locales/fr.json";
import ja from "../i18n/locales/ja.json";
import type { Language } from "../i18n/languages";
import type { TapSet } from "../landmarks";
import { describeAnswerPlace, describeLandmark, describeMarks, directionWords, placeIn } from "./describe";

const PHOTO = { width: 640, height: 480 };

/** An answer far off the photo, above it. */
const FAR: AnswerView = {
  ...NOTHING,
  kind: "elsewhere",
  drawing: { arrow: { direction: [0, -1] } } as unknown as AnswerView["drawing"],
};

function at(x: number, y: number, how: "solved" | "marked" | "on_line" = "solved", sure = true): AnswerView {
  const ellipse = sure ? { axes: [10, 5] as [number, number], angle_deg: 0 } : null;
  return {
    ...NOTHING,
    kind: "position",
    position: { x, y, ellipse, quality: "good", how } as AnswerView["position"],
  };
}

describe("placeIn", () => {
  it("names the ninth of the photo a point is in", () => {
    expect(placeIn({ x: 10, y: 10 }, PHOTO)).toBe("upper left");
    expect(placeIn({ x: 320, y: 10 }, PHOTO)).toBe("upper middle");
    expect(placeIn({ x: 320, y: 240 }, PHOTO)).toBe("centre");
    expect(placeIn({ x: 630, y: 240 }, PHOTO)).toBe("middle right");
    expect(placeIn({ x: 0, y: 480 }, PHOTO)).toBe("lower left");
  });

  it("says which way off the photo a point is", () => {
    expect(placeIn({ x: 700, y: 240 }, PHOTO)).toBe("off the photo to the right");
    expect(placeIn({ x: -5, y: -5 }, PHOTO)).toBe("off the photo above, to the left");
    expect(placeIn({ x: 320, y: 500 }, PHOTO)).toBe("off the photo below");
  });
});

describe("marks", () => {
  it("says a landmark's number, who placed it, where, and its state", () => {
    expect(describeLandmark(3, { x: 10, y: 10 }, PHOTO)).toBe("landmark 3, placed by you, upper left");
    expect(describeLandmark(4, { x: 600, y: 400 }, PHOTO, { suspect: true, selected: true })).toBe(
      "landmark 4, placed by you, lower right, to re-check, selected",
    );
  });

  it("lists the friend's mark first, then the landmarks by number", () => {
    const taps: TapSet = {
      landmarks: [
        { id: 2, x: 600, y: 20, sigma: null },
        { id: 1, x: 20, y: 460, sigma: null },
      ],
      friend: { x: 320, y: 240, sigma: null },
      friend_line: null,
    };
    expect(describeMarks(taps, PHOTO, 2, [1]).map((mark) => mark.key)).toEqual(["friend", "landmark 1", "landmark 2"]);
    expect(describeMarks(taps, PHOTO, 2, [1]).map((mark) => mark.words)).toEqual([
      "your friend, marked by you, centre",
      "landmark 1, placed by you, lower left, to re-check",
      "landmark 2, placed by you, upper right, selected",
    ]);
  });
});

describe("describeAnswerPlace", () => {
  it("says nothing before an answer", () => {
    expect(describeAnswerPlace(NOTHING, PHOTO)).toBeNull();
  });

  it("says where the frame is", () => {
    expect(describeAnswerPlace(at(100, 80), PHOTO)).toBe("your friend is inside the frame, upper left");
    expect(describeAnswerPlace(at(100, 80, "solved", false), PHOTO)).toBe(
      "your friend is most likely inside the frame, upper left",
    );
    expect(describeAnswerPlace(at(500, 400, "marked"), PHOTO)).toBe("your friend is at your mark, lower right");
    expect(describeAnswerPlace(at(320, 240, "on_line"), PHOTO)).toBe(
      "your friend is most likely inside the frame on your line, centre",
    );
    expect(describeAnswerPlace({ ...NOTHING, kind: "curve" }, PHOTO)).toBe(
      "your friend is somewhere on the curve drawn across the photo",
    );
  });

  it("says which way off the photo the friend is", () => {
    expect(describeAnswerPlace(at(900, 240), PHOTO)).toBe("your friend is off the photo to the right");
    expect(describeAnswerPlace(FAR, PHOTO)).toBe("your friend is far off the photo, above");
  });

  it("names the eight directions", () => {
    expect(directionWords([1, 0])).toBe("to the right");
    expect(directionWords([-0.7, 0.7])).toBe("below, to the left");
    expect(directionWords([0.7, -0.7])).toBe("above, to the right");
  });
});

/** The same marks and answers in each other language: the phone's own words, in its order. */
describe("in the language shown", () => {
  afterAll(async () => {
    await speak("en", en);
  });

  const CASES: [Language, Record<string, unknown>, string, string, string][] = [
    ["de", de, "Fixpunkt 3, von dir gesetzt, oben links, zu prüfen", "dein Freund ist rechts außerhalb des Fotos", "dein Freund ist weit oben außerhalb des Fotos"],
    ["es", es, "referencia 3, puesta por ti, arriba a la izquierda, por revisar", "tu amigo está fuera de la foto, a la derecha", "tu amigo está lejos, fuera de la foto, arriba"],
    ["fr", fr, "repère 3, placé par toi, en haut à gauche, à revoir", "ton ami est hors de la photo, à droite", "ton ami est loin hors de la photo, vers le haut"],
    ["ja", ja, "あなたが置いた目印3、左上、要確認", "友だちは写真の外の右側にいます", "友だちは写真のはるか外、上の方にいます"],
  ];

  for (const [language, words, landmark, off, away] of CASES) {
    it(`${language}: says a landmark and the friend's place in its own words`, async () => {
      await speak(language, words);
      const said = describeLandmark(3, { x: 10, y: 10 }, PHOTO, { suspect: true });
      expect(said).not.toBe("landmark 3, placed by you, upper left, to re-check");
      expect(said).toBe(landmark);
      expect(describeAnswerPlace(at(900, 240), PHOTO)).toBe(off);
      expect(describeAnswerPlace(FAR, PHOTO)).toBe(away);
    });
  }
});
