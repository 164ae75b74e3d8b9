import type { ReactNode } from "react";
import { Link } from "react-router";

import { HeldByOtherError } from "../../api/driveApi";
import type { ApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { nodeUrl } from "../../nav/paths";

/** A refused or failed run in the server's words; a held axis names its holder. */
export function RunError({ node, error }: { node: number; error: ApiError | null }): ReactNode {
  if (!error) return null;
  if (error instanceof HeldByOtherError) {
    const who = error.holder?.name ?? error.holder?.client_id ?? "another client";
    return (
      <div className="run-error">
        <ErrorText error={error} />
        <p className="small">
          {who} holds the axis: release it there, or take over control on the{" "}
          <Link to={nodeUrl(node, "drive")}>Drive page</Link> and release it, then run the step
          again.
        </p>
      </div>
    );
  }
  return <ErrorText error={error} />;
}
