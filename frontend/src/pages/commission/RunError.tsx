import type { ReactNode } from "react";
import { Link } from "react-router";

import { HeldByOtherError } from "../../api/driveApi";
import type { ApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { Trans, useTranslation } from "../../i18n";
import { nodeUrl } from "../../nav/paths";

/** A refused or failed run in the server's words; a held axis names its holder. */
export function RunError({ node, error }: { node: number; error: ApiError | null }): ReactNode {
  const { t } = useTranslation();
  if (!error) return null;
  if (error instanceof HeldByOtherError) {
    const who = error.holder?.name ?? error.holder?.client_id ?? t("commission.run.anotherClient");
    return (
      <div className="run-error">
        <ErrorText error={error} />
        <p className="small">
          <Trans
            i18nKey="commission.run.heldBy"
            values={{ who }}
            components={{ page: <Link to={nodeUrl(node, "drive")} /> }}
          />
        </p>
      </div>
    );
  }
  return <ErrorText error={error} />;
}
