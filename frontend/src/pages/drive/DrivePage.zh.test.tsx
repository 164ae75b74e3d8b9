// The Drive page in Simplified Chinese: cards, state machine, commands, jog and homing from the
// zh-CN catalogue; no English left on the main controls, no bare catalogue key anywhere.
import { screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { describe, expect, it } from "vitest";

import { inChinese } from "../../test/inChinese";
import { json, stubFetch } from "../../test/fetchStub";
import { CONTROLLER, DRIVE, ENABLED, METHODS } from "../../test/fixtures/drive";
import { renderPage } from "../../test/render";
import { DrivePage } from "./DrivePage";

inChinese();

/** Words of the English UI that must not be left on the page's controls. */
const ENGLISH =
  /\b(Enable|Disable|Shutdown|Switch on|Quick stop|Fault reset|Jog|Hold|Homing|Start homing|Statusword|Limits|Edit|Step|Move|Speed|Torque|Acceleration)\b/;

describe("DrivePage in zh-CN", () => {
  it("shows Chinese headings, state, commands and jog controls", async () => {
    stubFetch({
      "GET /api/nodes/1/drive": DRIVE,
      "GET /api/nodes/1/drive/controller": CONTROLLER,
      "GET /api/nodes/1/drive/homing-methods": METHODS,
    });
    const { container } = renderPage(<DrivePage node={1} />, "/nodes/1/drive");

    expect(document.documentElement.lang).toBe("zh-CN");
    await screen.findByRole("img", { name: /CiA 402 状态图：禁止合闸/ });
    expect(screen.getAllByRole("heading", { level: 2 }).map((h) => h.textContent)).toEqual([
      "状态机",
      "状态字",
      "实际值",
      "当前限值",
      "点动",
      "回零",
    ]);
    expect(screen.getByTestId("drive-state").textContent).toBe("禁止合闸");
    expect(screen.getByRole("button", { name: "使能" })).toBeTruthy();
    expect(screen.getByRole("button", { name: "去使能" })).toBeTruthy();
    const commands = within(screen.getByRole("group", { name: "状态机命令" }));
    expect(commands.getAllByRole("button").map((b) => b.getAttribute("aria-label"))).toEqual([
      "关闭",
      "合闸",
      "使能运行",
      "禁止运行",
      "断开电压",
      "快速停止",
      "故障复位",
    ]);
    const bits = within(screen.getByRole("list", { name: "状态字各位" }));
    expect(bits.getByLabelText("禁止合闸：亮")).toBeTruthy();
    expect(screen.getByLabelText("原点开关（HW）：亮")).toBeTruthy();
    expect(screen.getByTestId("mode").textContent).toBe("轮廓位置（PP）");
    expect(await screen.findByRole("radiogroup", { name: "回零方式" })).toBeTruthy();
    expect(screen.getByRole("button", { name: /^开始回零/ })).toBeTruthy();
    expect(screen.getByText("使能驱动器后才能回零。")).toBeTruthy();

    const jog = within(screen.getByRole("region", { name: "点动" }));
    expect(jog.getAllByRole("tab").map((tab) => tab.textContent)).toEqual([
      "轮廓位置（PP）",
      "轮廓速度（PV）",
      "轮廓转矩（PT）",
      "插补位置（IP）",
    ]);
    expect(jog.getByRole("button", { name: "加入序列" })).toBeTruthy();
    await userEvent.click(jog.getByRole("tab", { name: "轮廓速度（PV）" }));
    expect(jog.getByLabelText("加速度（rpm/s）")).toBeTruthy();
    expect(jog.getByRole("button", { name: /按住 \+60 rpm/ })).toBeTruthy();
    expect(jog.getByTestId("jog-pv-status").textContent).toContain("已停止");

    for (const control of container.querySelectorAll("button, h2, h3, label, dt, [role=tab]")) {
      expect(control.textContent, control.outerHTML.slice(0, 80)).not.toMatch(ENGLISH);
    }
    // a key the catalogue missed would show as "drive.…"
    expect(container.textContent).not.toMatch(/\bdrive\.[a-z]+\./);
  });

  it("names the enabled state and the motion buttons in Chinese", async () => {
    stubFetch({
      "GET /api/nodes/1/drive": ENABLED,
      "GET /api/nodes/1/drive/controller": CONTROLLER,
      "GET /api/nodes/1/drive/homing-methods": METHODS,
    });
    renderPage(<DrivePage node={1} />, "/nodes/1/drive");
    expect(await screen.findByTestId("drive-state")).toBeTruthy();
    expect(screen.getByTestId("drive-state").textContent).toBe("运行使能");
    expect(await screen.findByRole("button", { name: /^开始回零（方式 \d+）$/ })).toBeTruthy();
    expect(screen.getByRole("button", { name: /^步进 \+1 ▶$/ })).toBeTruthy();
  });

  it("says why it won't enable in Chinese, from the server's message ids", async () => {
    stubFetch({
      "GET /api/nodes/1/drive": DRIVE,
      "GET /api/nodes/1/drive/controller": CONTROLLER,
      "GET /api/nodes/1/drive/homing-methods": METHODS,
      "POST /api/nodes/1/drive/enable": json(
        {
          error: "enable_blocked",
          message: "node 1 does not enable",
          reasons: [
            {
              code: "nmt_not_operational",
              message: "the node is NMT pre-operational, not Operational: …",
              message_id: "reason.nmt_not_operational",
              params: { nmt: "pre-operational" },
            },
            {
              code: "voltage_disabled",
              message:
                "statusword bit 4 (voltage enabled) is 0: main power to the power stage is off",
              message_id: "reason.voltage_disabled",
              params: {},
            },
            { code: "timeout", message: "words of a newer server", message_id: "reason.newer" },
          ],
          state: DRIVE,
        },
        409,
      ),
    });
    renderPage(<DrivePage node={1} />, "/nodes/1/drive");
    await userEvent.click(await screen.findByRole("button", { name: "使能" }));
    const why = await screen.findByRole("alert");
    expect(
      within(why)
        .getAllByRole("listitem")
        .map((li) => li.textContent),
    ).toEqual([
      "节点处于 NMT 预操作，不是操作状态：它不理会控制 PDO——请启动它（NMT 启动）",
      "状态字位 4（电压使能）为 0：功率级主电源已断开",
      "words of a newer server",
    ]);
  });
});
