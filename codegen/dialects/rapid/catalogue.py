"""The instructions and functions of the RAPID manual by name: what a call the interpreter does not model is."""

from __future__ import annotations

# ABB, "Technical reference manual - RAPID Instructions, Functions and Data types" (RobotWare 6/7), chapters 1
# "Instructions" and 2 "Functions", by name as recalled (not every option package's instructions). A call of one
# of these that the interpreter does not model is refused by name ("... is not modelled"); a name in neither the
# program nor this list is an unknown routine.
_INSTRUCTIONS = """
ActUnit BitClear BitSet Break CallByVar CancelLoad CheckProgRef CirPathMode ClearIOBuff ClearPath ClearRawBytes
Close CloseDir Comment CopyFile CopyRawBytes CorrClear CorrCon CorrDiscon CorrWrite DeactUnit DitherAct DropWObj
EOffsOff EOffsOn EOffsSet EraseModule ErrLog GetDataVal GetSysData GetTrapData HollowWristReset
IDisable IEnable IError IPers IRMQMessage ISignalAI ISignalAO ISignalDO ISignalGI ISignalGO ISleep ITimer IVarValue
IWatch IndAMove IndCMove IndDMove IndReset IndRMove Load LoadId MakeDir MechUnitLoad MotionSup MoveCDO MoveCSync
MoveExtJ MoveJDO MoveJSync MoveLDO MoveLSync MToolRotCalib MToolTCPCalib Open OpenDir PackDNHeader PackRawBytes
PathAccLim PathRecMoveBwd PathRecMoveFwd PathRecStart PathRecStop PathResol PDispOff PDispOn PDispSet ProcerrRecovery
RaiseToUser ReadAnyBin ReadBlock ReadCfgData ReadErrData ReadRawBytes RemoveDir RemoveFile RenameFile ResetRetryCount
Rewind RMQEmptyQueue RMQFindSlot RMQGetMessage RMQGetMsgData RMQGetMsgHeader RMQReadWait RMQSendMessage
RMQSendWait SCWrite SearchC SearchExtJ SenDevice SetAllDataVal SetDataSearch SetDataVal SetSysData SkipWarn
SocketAccept SocketBind SocketClose SocketConnect SocketCreate SocketListen SocketReceive SocketSend SoftAct SoftDeact
SpeedRefresh SpyStart SpyStop StartLoad StartMove StartMoveRetry STCalib STClose StepBwdPath SToolRotCalib
SToolTCPCalib STOpen StopMove StopMoveReset SyncMoveOff SyncMoveOn SyncMoveResume SyncMoveSuspend
SyncMoveUndo SystemStopAction TestSignDefine TestSignReset TextTabInstall TPReadDnum TPShow TriggC TriggCheckIO
TriggEquip TriggInt TriggIO TriggJ TriggL TriggLIOs TriggRampAO TriggSpeed TriggStopProc TryInt TuneReset TuneServo
UIShow UnLoad UnpackRawBytes WaitAI WaitAO WaitGI WaitGO WaitLoad WaitSensor WaitSyncTask WaitTestAndSet WaitWObj
WarmStart WorldAccLim Write WriteAnyBin WriteBin WriteBlock WriteCfgData WriteStrBin WriteRawBytes WZBoxDef WZCylDef
WZDisable WZDOSet WZEnable WZFree WZHomeJointDef WZLimJointDef WZLimSup WZSphDef
"""
_FUNCTIONS = """
AbsDnum ArgName ByteToStr CalcJointT CalcRobT CalcRotAxisFrame CalcRotAxFrameZ CDate CorrRead CPos CSpeedOverride
CTool CWObj DecToHex DefAccFrame DefDFrame DefFrame DnumToNum DnumToStr EventType ExecHandler ExecLevel
FileSize FileTimeDnum FSSize GetMecUnitName GetNextMechUnit GetNextSym GetServiceInfo GetSignalOrigin GetSysInfo
GetMotorTorque GetTaskName GetTime HexToDec IndInpos IndSpeed IOUnitState IsFile IsMechUnitActive IsPers IsStopMoveAct
IsStopStateEvent IsSyncMoveOn IsSysId IsVar MirPos ModExist ModTime NonMotionMode NumToDnum ORobT
ParIdPosValid ParIdRobValid PathLevel PathRecValidBwd PathRecValidFwd PFRestart PPMovedInManMode ProgMemFree
RawBytesLen ReadBin ReadDir ReadMotor ReadNum ReadStr ReadStrBin ReadVar RemainingRetries RMQGetSlotName RobName
RobOS SocketGetStatus STCalcForce STCalcTorque STIsCalib STIsClosed STIsIndGun STIsOpen StrDigCalc
StrDigCmp StrToByte TaskRunMec TaskRunRob TasksInSync TestAndSet TestSignRead TextGet TextTabFreeToUse TextTabGet
Type UIAlphaEntry UIClientExist UIDnumEntry UIDnumTune UIListView UINumEntry UINumTune
"""
# Options' instructions and functions public programs call (Externally Guided Motion; YuMi's SmartGripper module).
_OPTIONS = """
EGMActJoint EGMActPose EGMGetId EGMGetState EGMReset EGMRunJoint EGMRunPose EGMSetupAI EGMSetupAO EGMSetupGI
EGMSetupLTAPP EGMSetupUC EGMStop EGMStreamStart EGMStreamStop g_Init g_Calibrate g_GripIn g_GripOut g_MoveTo g_JogIn
g_JogOut g_Stop g_BlowOn1 g_BlowOff1 g_VacuumOn1 g_VacuumOff1 g_GetPos g_IsCalibrated
"""
NOT_MODELLED = frozenset(name.upper() for name in (_INSTRUCTIONS + _FUNCTIONS + _OPTIONS).split())
