MODULE MainModule
  !***********************************************************
  ! Tray cell: takes parts from the feeder and puts them into
  ! the tray, one tray of nTrayParts parts per cycle.
  ! Data, tool and the pick/place routines: module CellData.
  !***********************************************************
  PERS num nPlaced := 0;
  VAR clock clkCycle;
  VAR part partNow;

  PROC main()
    TPErase;
    TPWrite "Tray cell: start";
    AccSet 70, 70;
    VelSet 80, 800;
    SingArea \Wrist;
    Reset doGripper;
    ClkReset clkCycle;
    ClkStart clkCycle;
    MoveAbsJ jHome, v1000, fine, tool0;
    nPlaced := 0;
  next_part:
    IF nPlaced >= nTrayParts GOTO tray_full;
    partNow := tray{nPlaced + 1};
    PickPart pFeeder;
    PlacePart partNow \Slow;
    Incr nPlaced;
    GOTO next_part;
  tray_full:
    ClkStop clkCycle;
    MoveAbsJ jHome, v1000, fine, tool0;
    PulseDO \PLength:=0.5, doTrayDone;
    TPWrite "Tray full, parts: " \Num:=nPlaced;
    TPWrite "Cycle time [s]: " \Num:=Round(ClkRead(clkCycle) \Dec:=1);
  ENDPROC
ENDMODULE
