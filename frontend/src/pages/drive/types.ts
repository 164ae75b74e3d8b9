// The Drive tab's types are the motion API's, in api/drive.ts (live/ and other pages use them
// too); re-exported so the tab's modules import them from beside them.
export type * from "../../api/drive";
