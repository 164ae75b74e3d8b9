// The Commission tab's types are the commissioning API's, in api/commission.ts (the Network
// page's node list uses them too); re-exported so the tab's modules import them from beside them.
export type * from "../../api/commission";
