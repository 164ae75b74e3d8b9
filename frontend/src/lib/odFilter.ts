// The object-dictionary search box. Engineers type addresses the way manuals print them:
// "6041", "0x6041", "6041h", "1018:2", "2006:0A" (sub-index in hex, like the API), or part of a
// name ("statusword"). A bare hex-looking word such as "60" or "add" could be either, so it
// matches index prefixes and names alike.
import type { OdEntry, OdObject } from "../api/types";

export type OdQuery =
  | { kind: "all" }
  | {
      kind: "address";
      indexPrefix: string;
      exact: boolean;
      sub: number | null;
      name: string | null;
    }
  | { kind: "name"; name: string };

const ADDRESS = /^(0x)?([0-9a-f]{1,4})h?(?:\s*(?::|\.|sub)\s*(?:0x)?([0-9a-f]{1,2})h?)?$/i;

export function parseOdQuery(raw: string): OdQuery {
  const text = raw.trim();
  if (!text) return { kind: "all" };
  const match = ADDRESS.exec(text);
  if (match) {
    const [, prefix, digits = "", subText] = match;
    const sub = subText === undefined ? null : Number.parseInt(subText, 16);
    // "0x60" and "1018:2" are unmistakably addresses; "60" or "add" may also be a name.
    const nameToo = prefix === undefined && sub === null && !/h$/i.test(text);
    return {
      kind: "address",
      indexPrefix: digits.toUpperCase(),
      // With a sub-index, or written with 0x/h, or all four digits, the index is meant exactly.
      exact: sub !== null || digits.length === 4 || /h$/i.test(text.split(/[:.]/)[0] ?? ""),
      sub,
      name: nameToo ? text.toLowerCase() : null,
    };
  }
  return { kind: "name", name: text.toLowerCase() };
}

export interface FilteredObject {
  object: OdObject;
  /** Subs to list under the object. */
  subs: readonly OdEntry[];
  /** True when the match is in the subs, so the object should open to show them. */
  openForMatch: boolean;
}

function indexHex(object: OdObject): string {
  return object.index.toString(16).toUpperCase().padStart(4, "0");
}

function byName(object: OdObject, name: string): FilteredObject | null {
  if (object.name.toLowerCase().includes(name)) {
    return { object, subs: object.subs, openForMatch: false };
  }
  const subs = object.subs.filter((s) => s.name.toLowerCase().includes(name));
  return subs.length > 0 ? { object, subs, openForMatch: true } : null;
}

export function filterOd(objects: readonly OdObject[], query: OdQuery): FilteredObject[] {
  if (query.kind === "all") {
    return objects.map((object) => ({ object, subs: object.subs, openForMatch: false }));
  }
  const result: FilteredObject[] = [];
  for (const object of objects) {
    if (query.kind === "name") {
      const hit = byName(object, query.name);
      if (hit) result.push(hit);
      continue;
    }
    const hex = indexHex(object);
    const indexHit = query.exact
      ? hex === query.indexPrefix.padStart(4, "0")
      : hex.startsWith(query.indexPrefix);
    if (indexHit) {
      if (query.sub === null) {
        result.push({ object, subs: object.subs, openForMatch: false });
      } else {
        const subs = object.subs.filter((s) => s.subindex === query.sub);
        if (subs.length > 0) result.push({ object, subs, openForMatch: true });
      }
      continue;
    }
    if (query.name !== null) {
      const hit = byName(object, query.name);
      if (hit) result.push(hit);
    }
  }
  return result;
}

/** Number of entries (subs) in a filtered list, for the "n of m" hint. */
export function countEntries(list: readonly FilteredObject[]): number {
  return list.reduce((n, f) => n + f.subs.length, 0);
}
