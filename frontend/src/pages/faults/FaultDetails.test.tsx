// A fault on the Faults tab: in zh-CN the Chinese name, cause and what to check, a name
// ServoDesk translated (Kinco's manual and the CiA tables are English only) marked as
// ServoDesk's, its title naming the source, and the source's own words under a fold; in English
// the English as before.
import { render, screen } from "@testing-library/react";
import { describe, expect, it } from "vitest";

import type { Fault } from "../../api/faults";
import { inChinese } from "../../test/inChinese";
import { mdiAlarm4 } from "../../test/fixtures/faults";
import { FaultDetails } from "./FaultDetails";

function kincoFollowing(overrides: Partial<Fault> = {}): Fault {
  return mdiAlarm4({
    node: 2,
    code: 0x8611,
    code_hex: "0x8611",
    name_en: "Following error too high",
    name_zh: "跟随误差过大",
    name_zh_source: "translation",
    check:
      "Cause: The position error exceeded 6065h. Check: gains, load. Source: Kinco servo CANopen manual §8.",
    raw_hex: "11 86 00 00 00 00 00 00",
    ...overrides,
  });
}

function meaning(): HTMLElement {
  const term = screen.getAllByRole("term").find((dt) => /含义|Meaning/.test(dt.textContent));
  return term?.nextElementSibling as HTMLElement;
}

describe("FaultDetails in zh-CN", () => {
  inChinese();

  it("shows a translated name, marked as ServoDesk's, the source's English under a fold", () => {
    render(<FaultDetails fault={kincoFollowing()} />);
    const names = meaning();
    expect(names.textContent).toBe("跟随误差过大ServoDesk 译文");
    expect(names.querySelector(".fault-name-first")?.textContent).toBe("跟随误差过大");
    const fold = screen.getByText("原文（来源的原话）").closest("details");
    expect(fold?.open).toBe(false);
    expect(fold?.querySelector(".fault-name-source")?.textContent).toBe("Following error too high");
    const marker = screen.getByText("ServoDesk 译文");
    expect(marker.getAttribute("title")).toBe(
      "中文由 ServoDesk 译自 Kinco servo CANopen manual §8 的英文原文",
    );
  });

  it("names the CiA table when the check has no source", () => {
    render(
      <FaultDetails
        fault={kincoFollowing({
          source: "cia402",
          name_en: "Following error",
          check: "CiA class: monitoring.",
        })}
      />,
    );
    expect(screen.getByText("ServoDesk 译文").getAttribute("title")).toBe(
      "中文由 ServoDesk 译自 CiA 402（设备子协议） 的英文原文",
    );
  });

  it("shows the MDi manual's own Chinese first too, unmarked", () => {
    render(<FaultDetails fault={mdiAlarm4({ name_zh_source: "manual" })} />);
    expect(meaning().textContent).toBe("位置超差");
    expect(screen.queryByText("ServoDesk 译文")).toBeNull();
  });

  it("says the cause and what to check in Chinese, the marker naming the Chinese source", () => {
    render(
      <FaultDetails
        fault={kincoFollowing({
          check_zh:
            "原因：位置误差超出 6065h。 检查：增益、负载。 来源：步科伺服 CANopen 手册 §8。",
        })}
      />,
    );
    const items = [...document.querySelectorAll("dd > .fault-check > li")].map(
      (li) => li.textContent,
    );
    expect(items).toEqual([
      "原因：位置误差超出 6065h。",
      "检查：增益、负载。",
      "来源：步科伺服 CANopen 手册 §8。",
    ]);
    expect(screen.getByText("ServoDesk 译文").getAttribute("title")).toBe(
      "中文由 ServoDesk 译自 步科伺服 CANopen 手册 §8 的英文原文",
    );
    const english = [...document.querySelectorAll("details .fault-check > li")].map(
      (li) => li.textContent,
    );
    expect(english).toEqual([
      "Cause: The position error exceeded 6065h.",
      "Check: gains, load.",
      "Source: Kinco servo CANopen manual §8.",
    ]);
  });
});

describe("FaultDetails in English", () => {
  it("shows a translated name's English alone", () => {
    render(<FaultDetails fault={kincoFollowing()} />);
    expect(meaning().textContent).toBe("Following error too high");
    expect(screen.queryByText("ServoDesk translation")).toBeNull();
  });

  it("keeps the MDi's English first and its manual's Chinese beside it, as before", () => {
    render(<FaultDetails fault={mdiAlarm4({ name_zh_source: "manual" })} />);
    const names = meaning();
    expect(names.querySelector(".fault-name-en")?.textContent).toBe("Following error");
    expect(names.querySelector(".fault-name-zh")?.textContent).toBe("位置超差");
    // a row stored before faults said where their Chinese came from reads as before
    render(<FaultDetails fault={mdiAlarm4({ name_zh_source: null })} />);
    expect(screen.getAllByText("位置超差")).toHaveLength(2);
  });
});
