"""The simulated controller's $config.dat: KUKA's types, defaults and names every KSS 8 program may use."""

from __future__ import annotations

# A KUKA controller's R1/System/$config.dat declares the types of the inline forms (PDAT, LDAT, FDAT...),
# the BAS defaults (DEF_VEL_CP...), the home positions (XHOME, XHOME1..5), the default motion data (PDEFAULT,
# LDEFAULT, FDEFAULT, FHOME) and the integrator's global names (signals, variables: the "USER GLOBALS" fold);
# every name it declares is global to every module (KSS 8 programming manual for system integrators, data
# lists: $CONFIG.DAT). The interpreter brings the one below: the types and defaults a KSS 8 controller is
# shipped with (values as shipped; XHOME = the axes at 0, -90, 90, 0, 0, 0), written for the interpreter.
# A $config.dat given among a program's files is read after it: its declarations replace these (its own
# XHOME, its signals, its TOOL_DATA / BASE_DATA / LOAD_DATA values). TOOL_DATA, BASE_DATA and LOAD_DATA are
# not declared here: the interpreter does not know a controller's tools and bases (codegen/dialects/krl/
# numbered.py: --input TOOL_DATA[n]=... or a given $config.dat sets them; an entry nothing sets is a fresh
# controller's, and a run that uses it warns).
# The AUTOEXT GLOBALS below (Automatic External: the program number a PLC sends, read by KUKA's P00 module)
# are the names, types and values of KSS 8 $config.dat files as shipped (seen in controllers' backups; the
# manual for system integrators lists the variables, its values were not readable here: not confirmed).
NAME = "built-in $config.dat"  # the name the built-in module's messages carry (not a file of the user's)
CONFIG_DAT = (
    "\n".join(
        (
            "DEFDAT $CONFIG PUBLIC",
            "; the enumerations and structures of KUKA's inline forms and BAS",
            "ENUM BAS_COMMAND INITMOV,ACC_CP,ACC_PTP,VEL_CP,VEL_PTP,ACC_GLUE,TOOL,BASE,EX_BASE,PTP_DAT,"
            "CP_DAT,OUT_SYNC,OUT_ASYNC,GROUP,FRAMES,PTP_PARAMS,CP_PARAMS",
            "ENUM APO_MODE_T CPTP,CDIS",
            "ENUM IPO_M_T NONE,TCP,BASE",
            "ENUM OUT_MODETYPE TRIGGER_,CONT_,STOP_",
            "ENUM ORI_TYPE CONSTANT,VAR,JOINT",
            "ENUM CIRC_TYPE BASE,PATH",
            "ENUM IPO_MODE BASE,TCP",
            "STRUC PDAT REAL VEL,ACC,APO_DIST,APO_MODE_T APO_MODE,REAL GEAR_JERK,INT EXAX_IGN",
            "STRUC LDAT REAL VEL,ACC,APO_DIST,APO_FAC,AXIS_VEL,AXIS_ACC,ORI_TYPE ORI_TYP,CIRC_TYPE CIRC_TYP,"
            "REAL JERK_FAC,GEAR_JERK,INT EXAX_IGN,CIRC_MODE CB",
            "STRUC FDAT INT TOOL_NO,BASE_NO,IPO_MODE IPO_FRAME,CHAR POINT2[24],BOOL TQ_STATE",
            "STRUC ODAT INT OUT_NO,BOOL STATE,REAL PULSE_TIME,OUT_MODETYPE OUT_MODE,REAL TIME_DELAY,OFFSET",
            "STRUC BASIS_SUGG_T CHAR POINT1[24],POINT2[24],CP_PARAMS[24],PTP_PARAMS[24],CONT[24],CP_VEL[24],"
            "PTP_VEL[24],SYNC_PARAMS[24],SPL_NAME[24],A_PARAMS[24]",
            "STRUC OUT_SUGG_T CHAR PARAMS[24]",
            "STRUC TM_SUGG_T CHAR TM_ID[24]",
            "STRUC MODULEPARAM_T CHAR PARAMS[2000]",
            "STRUC TRIGGER_PARA INT TRIGGERPATH,BOOL TRIGGERONSTART,INT TRIGGERDELAY,CHAR TRIGGERTASK[40]",
            "STRUC CONSTVEL_PARA INT CONSTVELTYP,INT CONSTVELPATH,BOOL CONSTVELONSTART",
            "STRUC CONDSTOP_PARA INT CONDSTOPPATH,BOOL CONDSTOPONSTART,CHAR STOPCONDITION[40]",
            "STRUC ADAT TRIGGER_PARA TRIGGERPARA,CONSTVEL_PARA CONSTVELPARA,CONDSTOP_PARA CONDSTOPPARA",
            "STRUC TQM_TQDAT_T INT T11,T12,T13,T14,T15,T16,T21,T22,T23,T24,T25,T26,K1,K2,K3,K4,K5,K6,O1,O2,"
            "ID,OVM,REAL TMF",
            "; BAS's defaults (KSS 8 as shipped)",
            "INT DEF_OV_PRO=100",
            "INT DEF_ADVANCE=3",
            "INT DEF_VEL_PTP=100",
            "INT DEF_ACC_PTP=50",
            "DECL CIRC_TYPE DEF_CIRC_TYP=#BASE",
            "REAL DEF_VEL_CP=2.0",
            "REAL DEF_VEL_ORI1=200.0",
            "REAL DEF_VEL_ORI2=200.0",
            "REAL DEF_ACC_CP=2.3",
            "REAL DEF_ACC_ORI1=100.0",
            "REAL DEF_ACC_ORI2=100.0",
            "INT DEF_APO_CPTP=50",
            "INT DEF_APO_CVEL=100",
            "REAL DEF_APO_CDIS=3.0",
            "REAL DEF_APO_CORI=5.0",
            "EXT BAS (BAS_COMMAND :IN,REAL :IN )",
            "EXT IR_STOPM ( )",
            "; the inline forms' default motion data and the data BAS reads",
            "DECL PDAT PDEFAULT={VEL 100.0,ACC 100.0,APO_DIST 100.0,APO_MODE #CDIS,GEAR_JERK 50.0,EXAX_IGN 0}",
            "DECL LDAT LDEFAULT={VEL 2.0,ACC 100.0,APO_DIST 100.0,APO_FAC 50.0,AXIS_VEL 100.0,"
            "AXIS_ACC 100.0,ORI_TYP #VAR,CIRC_TYP #BASE,JERK_FAC 50.0,GEAR_JERK 50.0,EXAX_IGN 0}",
            'DECL FDAT FDEFAULT={TOOL_NO 1,BASE_NO 0,IPO_FRAME #BASE,POINT2[] " ",TQ_STATE FALSE}',
            'DECL FDAT FHOME={TOOL_NO 1,BASE_NO 0,IPO_FRAME #BASE,POINT2[] " ",TQ_STATE FALSE}',
            "DECL ODAT ODEFAULT={OUT_NO 1,STATE TRUE,PULSE_TIME 0.0,OUT_MODE #STOP_,TIME_DELAY 0.0,OFFSET 0.0}",
            "DECL PDAT PDAT_ACT",
            "DECL LDAT LDAT_ACT",
            "DECL FDAT FDAT_ACT",
            "DECL ODAT ODAT_ACT",
            "DECL CHAR SPL_NAME[24]",
            "; the home positions",
            "E6AXIS XHOME={A1 0.0,A2 -90.0,A3 90.0,A4 0.0,A5 0.0,A6 0.0,E1 0.0,E2 0.0,E3 0.0,E4 0.0,E5 0.0,E6 0.0}",
            "E6AXIS XHOME1={A1 0.0,A2 -90.0,A3 90.0,A4 0.0,A5 0.0,A6 0.0,E1 0.0,E2 0.0,E3 0.0,E4 0.0,E5 0.0,E6 0.0}",
            "E6AXIS XHOME2={A1 0.0,A2 -90.0,A3 90.0,A4 0.0,A5 0.0,A6 0.0,E1 0.0,E2 0.0,E3 0.0,E4 0.0,E5 0.0,E6 0.0}",
            "E6AXIS XHOME3={A1 0.0,A2 -90.0,A3 90.0,A4 0.0,A5 0.0,A6 0.0,E1 0.0,E2 0.0,E3 0.0,E4 0.0,E5 0.0,E6 0.0}",
            "E6AXIS XHOME4={A1 0.0,A2 -90.0,A3 90.0,A4 0.0,A5 0.0,A6 0.0,E1 0.0,E2 0.0,E3 0.0,E4 0.0,E5 0.0,E6 0.0}",
            "E6AXIS XHOME5={A1 0.0,A2 -90.0,A3 90.0,A4 0.0,A5 0.0,A6 0.0,E1 0.0,E2 0.0,E3 0.0,E4 0.0,E5 0.0,E6 0.0}",
            "INT MAX_TOOL=16",
            "INT MAX_BASE=32",
            "; Automatic External's globals (the AUTOEXT GLOBALS fold; P00 itself is refused by name)",
            "ENUM FUNCT_TYPE PGNO_GET,PGNO_ACKN,PGNO_FAULT",
            "ENUM P00_COMMAND INIT_EXT,EXT_PGNO,CHK_HOME,EXT_ERR",
            "STRUC SPS_PROG_TYPE INT PROG_NR,CHAR PROG_NAME[12]",
            "BOOL ERROR_FLAG",
            "BOOL CHECK_HOME=TRUE",
            "BOOL PROG_CONTROL=FALSE",
            "INT PGNO=0",
            "INT PGNO_ERROR=0",
            "INT PGNO_TYPE=1",
            "INT REFLECT_PROG_NR=0",
            "INT PGNO_FBIT=33",
            "INT PGNO_FBIT_REFL=999",
            "INT PGNO_LENGTH=8",
            "INT PGNO_PARITY=41",
            "INT PGNO_REQ=33",
            "INT PGNO_VALID=42",
            "INT APPL_RUN=34",
            "INT ERR_TO_PLC=35",
            "INT P01_STEP",
            "INT CHK_STEP",
            "INT PGNO_FLAG",
            "ENDDAT",
        )
    )
    + "\n"
)


def is_config(name: str) -> bool:
    """A program file that is the controller's $config.dat (any folder, any case)."""
    base = name.replace("\\", "/").rsplit("/", 1)[-1]
    return base.lower() == "$config.dat"
