import { describe, expect, it } from "vitest";

import type { OdEntry, OdObject } from "../api/types";
import { countEntries, filterOd, parseOdQuery } from "./odFilter";

function entry(index: number, subindex: number, name: string): OdEntry {
  return {
    index,
    subindex,
    name,
    data_type: 7,
    data_type_name: "UNSIGNED32",
    access: "ro",
    pdo_mappable: false,
    unit: "",
    description: "",
  };
}

function object(index: number, name: string, subs: [number, string][] = [[0, name]]): OdObject {
  return {
    index,
    index_hex: index.toString(16).toUpperCase().padStart(4, "0"),
    name,
    object_type: subs.length > 1 ? "record" : "var",
    subs: subs.map(([sub, subName]) => entry(index, sub, subName)),
  };
}

const OD: OdObject[] = [
  object(0x1000, "Device type"),
  object(0x1018, "Identity object", [
    [0, "Highest sub-index supported"],
    [1, "Vendor-ID"],
    [2, "Product code"],
    [3, "Revision number"],
    [4, "Serial number"],
  ]),
  object(0x2006, "Drive parameters", [
    [0, "Number of entries"],
    [0x0a, "PA-105 node address"],
    [0x10, "PA-111"],
  ]),
  object(0x6040, "Controlword"),
  object(0x6041, "Statusword"),
  object(0x6060, "Modes of operation"),
  object(0x0add, "Hex-named type"),
];

const indices = (query: string): string[] =>
  filterOd(OD, parseOdQuery(query)).map((f) => f.object.index_hex);

describe("OD search", () => {
  it.each([
    ["", ["1000", "1018", "2006", "6040", "6041", "6060", "0ADD"]],
    ["6041", ["6041"]],
    ["0x6041", ["6041"]],
    ["6041h", ["6041"]],
    ["0x60", ["6040", "6041", "6060"]],
    ["604", ["6040", "6041"]],
    ["status", ["6041"]],
    ["STATUSWORD", ["6041"]],
    ["word", ["6040", "6041"]],
    ["1018:2", ["1018"]],
    ["1018:9", []],
    ["zzz", []],
  ])("%j finds %j", (query, expected) => {
    expect(indices(query)).toEqual(expected);
  });

  it("narrows an index:sub query to that entry and opens its object", () => {
    const [hit] = filterOd(OD, parseOdQuery("1018:2"));
    expect(hit?.subs.map((s) => s.name)).toEqual(["Product code"]);
    expect(hit?.openForMatch).toBe(true);
  });

  it("reads the sub-index as hex, like the API", () => {
    const [hit] = filterOd(OD, parseOdQuery("2006:0A"));
    expect(hit?.subs.map((s) => s.subindex)).toEqual([0x0a]);
    expect(filterOd(OD, parseOdQuery("2006:10"))[0]?.subs[0]?.subindex).toBe(0x10);
  });

  it("matches names of sub-entries and opens their object", () => {
    const hits = filterOd(OD, parseOdQuery("serial"));
    expect(hits).toHaveLength(1);
    expect(hits[0]?.object.index_hex).toBe("1018");
    expect(hits[0]?.subs.map((s) => s.subindex)).toEqual([4]);
    expect(hits[0]?.openForMatch).toBe(true);
  });

  it("takes a hex-looking word as index prefix and as name", () => {
    // "add" is hex (0ADD) and also part of "PA-105 node address".
    expect(indices("add")).toEqual(["2006"]); // index prefix ADD… matches nothing; names do
    expect(indices("0add")).toEqual(["0ADD"]);
  });

  it("counts the entries shown", () => {
    expect(countEntries(filterOd(OD, parseOdQuery("")))).toBe(13);
    expect(countEntries(filterOd(OD, parseOdQuery("1018")))).toBe(5);
  });

  it("filters a 1000+ entry dictionary quickly", () => {
    const big: OdObject[] = [];
    for (let i = 0; i < 400; i += 1) {
      big.push(
        object(0x2000 + i, `Vendor object ${i}`, [
          [0, "count"],
          [1, "first value"],
          [2, "second value"],
        ]),
      );
    }
    const start = performance.now();
    for (const q of ["2", "20", "200", "2001", "valu", "second", "2001:2"])
      filterOd(big, parseOdQuery(q));
    expect(performance.now() - start).toBeLessThan(500);
  });
});
