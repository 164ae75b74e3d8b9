// The catalogues: a pair of files per page area beside the shell's (en.json, zh-CN.json), merged
// here; an area's keys are its file's top-level names, which no other file uses. `server` holds
// the server's texts by message id (lib/serverText.ts), English word for word as the server's.
import drive from "./locales/drive.en.json";
import driveZh from "./locales/drive.zh-CN.json";
import commission from "./locales/commission.en.json";
import commissionZh from "./locales/commission.zh-CN.json";
import en from "./locales/en.json";
import faults from "./locales/faults.en.json";
import faultsZh from "./locales/faults.zh-CN.json";
import logs from "./locales/logs.en.json";
import logsZh from "./locales/logs.zh-CN.json";
import od from "./locales/od.en.json";
import odZh from "./locales/od.zh-CN.json";
import params from "./locales/params.en.json";
import paramsZh from "./locales/params.zh-CN.json";
import pdo from "./locales/pdo.en.json";
import pdoZh from "./locales/pdo.zh-CN.json";
import scope from "./locales/scope.en.json";
import scopeZh from "./locales/scope.zh-CN.json";
import server from "./locales/server.en.json";
import serverZh from "./locales/server.zh-CN.json";
import zhCN from "./locales/zh-CN.json";

export const EN = {
  ...en,
  ...commission,
  ...drive,
  ...faults,
  ...logs,
  ...od,
  ...params,
  ...pdo,
  ...scope,
  ...server,
};
export const ZH_CN = {
  ...zhCN,
  ...commissionZh,
  ...driveZh,
  ...faultsZh,
  ...logsZh,
  ...odZh,
  ...paramsZh,
  ...pdoZh,
  ...scopeZh,
  ...serverZh,
};
