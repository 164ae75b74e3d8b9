import { useState, type ReactNode } from "react";

import type { HeldByOtherError } from "../../api/driveApi";
import { ErrorText } from "../../components/ErrorText";
import { nmtStateText } from "../../components/NmtDot";
import { QuickStopButton } from "../../components/QuickStopButton";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { serverText } from "../../lib/serverText";
import { useLive } from "../../live/context";
import { ControllerBar } from "./ControllerBar";
import { DriveControls } from "./DriveControls";
import { DriveValues } from "./DriveValues";
import { HomingWizard } from "./HomingWizard";
import { JogPanel } from "./JogPanel";
import { LimitsCard } from "./LimitsCard";
import { manualFor } from "./manuals";
import { StateDiagram } from "./StateDiagram";
import { stateLabel } from "./stateMachine";
import { StatusLamps } from "./StatusLamps";
import { useController, useDrive } from "./useDrive";

/** The CiA 402 drive panel: state machine, statusword, actual values, limits, control lease,
 * jog per mode and homing — with Quick stop always one click away. */
export function DrivePage({ node }: { node: number }): ReactNode {
  const { t } = useTranslation();
  const { drive, error, show } = useDrive(node);
  const controller = useController(node);
  const [heldBy, setHeldBy] = useState<HeldByOtherError | null>(null);
  const mayCommand = !(controller.controller?.holder && !controller.controller.you);
  const profile = useLive((s) => s.infos.find((i) => i.node === node)?.profile);

  return (
    <div className="drive-page">
      <div className="drive-bar" role="toolbar" aria-label={t("drive.page.toolbar")}>
        <QuickStopButton node={node} onStopped={show} />
        {drive && (
          <span className={`badge drive-state state-${drive.state}`} data-testid="drive-state">
            {stateLabel(drive.state)}
          </span>
        )}
        {drive && drive.nmt_state !== "operational" && (
          <span className="badge drive-warn">
            {t("drive.page.nmtWarn", { state: nmtStateText(drive.nmt_state) })}
          </span>
        )}
        <span className="spacer" />
        <ControllerBar node={node} controller={controller.controller} show={controller.show} />
      </div>
      {heldBy && (
        <p className="error-text" role="alert">
          {heldBy.text()}{" "}
          <button type="button" className="small" onClick={() => setHeldBy(null)}>
            {t("drive.page.dismiss")}
          </button>
        </p>
      )}
      <ErrorText error={error ?? controller.error} />
      {!drive ? (
        !error && <Spinner label={t("drive.page.reading")} />
      ) : (
        <>
          <div className="drive-grid">
            <section className="card drive-machine" aria-labelledby="drive-machine-heading">
              <header className="card-header">
                <h2 id="drive-machine-heading">{t("drive.page.stateMachine")}</h2>
                <span className="muted small">{manualFor(profile, "state_machine")}</span>
              </header>
              <StateDiagram state={drive.state} lastTransition={drive.last_transition} />
              {drive.last_transition && (
                <p className="muted small">
                  {t("drive.page.lastTransition", {
                    transition: serverText({
                      message: drive.last_transition,
                      message_id: drive.last_transition_id,
                      params: drive.last_transition_params,
                    }),
                  })}
                </p>
              )}
              <DriveControls
                node={node}
                drive={drive}
                show={show}
                mayCommand={mayCommand}
                onHeldByOther={setHeldBy}
              />
            </section>
            <div className="drive-side">
              <StatusLamps drive={drive} />
              <DriveValues drive={drive} />
              <LimitsCard node={node} drive={drive} mayCommand={mayCommand} />
            </div>
          </div>
          <JogPanel node={node} drive={drive} show={show} mayCommand={mayCommand} />
          <HomingWizard node={node} drive={drive} show={show} mayCommand={mayCommand} />
        </>
      )}
    </div>
  );
}
