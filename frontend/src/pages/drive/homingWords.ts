// The homing methods' names, descriptions and path words in the page's language. The server
// sends them in English (GET …/drive/homing-methods); the five methods ServoDesk draws have
// their words in the catalogue, English word for word as the server's
// (tests/backend/test_homing_words.py); a method or word the page does not know stays as sent.
import type { HomingMethodInfo } from "../../api/drive";
import { currentLanguage, i18n, type MessageKey } from "../../i18n";

const METHODS: Partial<Record<number, { name: MessageKey; description: MessageKey }>> = {
  17: { name: "drive.homingMethod.m17.name", description: "drive.homingMethod.m17.description" },
  18: { name: "drive.homingMethod.m18.name", description: "drive.homingMethod.m18.description" },
  23: { name: "drive.homingMethod.m23.name", description: "drive.homingMethod.m23.description" },
  27: { name: "drive.homingMethod.m27.name", description: "drive.homingMethod.m27.description" },
  35: { name: "drive.homingMethod.m35.name", description: "drive.homingMethod.m35.description" },
};

/** The server's words for where a path step ends → their catalogue key. */
export const UNTIL: Readonly<Record<string, MessageKey>> = {
  "negative limit switch rises": "drive.homingUntil.negativeRises",
  "negative limit switch falls (home)": "drive.homingUntil.negativeFalls",
  "positive limit switch rises": "drive.homingUntil.positiveRises",
  "positive limit switch falls (home)": "drive.homingUntil.positiveFalls",
  "home switch rises": "drive.homingUntil.homeRises",
  "home switch falls at its lower edge (home)": "drive.homingUntil.homeLowerEdge",
  "home switch falls at its upper edge (home)": "drive.homingUntil.homeUpperEdge",
};

export function methodName(method: Pick<HomingMethodInfo, "method" | "name">): string {
  const keys = METHODS[method.method];
  return currentLanguage() === "en" || !keys ? method.name : i18n.t(keys.name);
}

export function methodDescription(
  method: Pick<HomingMethodInfo, "method" | "description">,
): string {
  const keys = METHODS[method.method];
  return currentLanguage() === "en" || !keys ? method.description : i18n.t(keys.description);
}

/** Where a path step ends ("home switch rises"), in the page's language. */
export function untilWords(until: string): string {
  const key = UNTIL[until];
  return currentLanguage() === "en" || !key ? until : i18n.t(key);
}
