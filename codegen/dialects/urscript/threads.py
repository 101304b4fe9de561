"""URScript threads (`thread`, `run`, `kill`, `join`): one controller frame at a time while the program spends time."""

# URScript Script Directory (e-Series), 10 Threads (STATED):
# - `thread name(): ... end`; "A thread cannot take parameters, and its return value is discarded. Threads
#   can be nested, forming a thread hierarchy." `h = run name()` starts it and returns a handle; `join h`
#   "halts the calling thread until the specified thread finishes. If already finished, join has no effect";
#   `kill h` "stops the running thread and invalidates its handle. If the thread has children, they are
#   killed too." (10.1) "The scoping rules for threads are exactly the same, as those used for functions."
# - 10.2 Thread Scheduling: the robot is controlled at 500 Hz; each 0.002 s is a frame and each thread gets
#   a "physical" time slice of 0.002 s per frame. sleep and sync use physical time (sync(): "uses up the
#   remaining 'physical' time a thread has in the current frame"). A thread that does not use its slice must
#   become non-runnable (join, or terminate) before the frame ends; "if this expectation is not met, the
#   program is stopped" ("Lost communication with Controller" and a protective stop: put sync() or sleep in
#   loops that do not control the robot).
#
# Modelled so (deterministic): the main program's statements take no time; its moves, sleep and sync()
# advance the machine's clock (codegen/dialects/core/machine.py). A thread runs one slice at each controller
# cycle the clock passes (the core's "every" watcher, Machine.watching, at the run's signal cycle: 2 ms on the
# e-Series): from where it stopped to its next sync() (or into a sleep, which skips the frames until it
# ends). Its slice sees the machine's clock at that cycle: get_actual_tcp_pose() is the TCP there, an input
# its value at that cycle. Each URScript thread runs in a greenlet (a coroutine with its own stack: exactly
# one of the program and its threads runs at any time, switched explicitly), so the order is the same on
# every run and a slice costs a switch, not an operating system's thread hand-off.
# Assumed (not in the manual): a thread's first slice is the first cycle after `run` (the controller runs it
# once the main program has used up its own slice, i.e. on its next move, sleep or sync()); a thread that
# runs THREAD_FRAME_STEPS statements in one slice without sync() or sleep() is one that does not give up its
# frame: the program stops (a RunError here, naming the thread and where it was); a move from a thread is
# not modelled (RunError); the program's end kills its threads; killing a handle already killed, or joining
# it, is an error (the manual: kill "invalidates its handle").

from __future__ import annotations

import math

from greenlet import getcurrent, greenlet

from codegen.dialects.core.machine import Frame, Routine
from codegen.dialects.core.values import RunError, StepLimitError, describe

THREAD_FRAME_STEPS = 10_000  # statements a thread may run within one frame (assumed, see above)
STEP_TIME_S = 0.002  # the e-Series frame, where the run has no signal cycle of its own (ordinary runs)
WATCH_NAME = "<urscript threads>"  # the core watcher's input name: none ("every" fires each cycle)


class Killed(BaseException):
    """Unwinds a killed thread's Python stack (a BaseException: nothing in the compiled code catches it)."""


class URThread:
    """A running thread (the value `run` returns: its handle)."""

    def __init__(self, scheduler: Scheduler, routine, parent: URThread | None, where: str) -> None:
        self.scheduler, self.routine, self.parent, self.where = scheduler, routine, parent, where
        self.name = routine.name
        self.children: list[URThread] = []
        self.state = "new"  # "new", "running" (between frames), "done", "killed"
        self.wake = -math.inf  # sleeping until this time
        self.error: BaseException | None = None
        self.watcher = None
        self.glet: greenlet | None = None  # the thread's coroutine (created at its first slice)
        self.caller = None  # the greenlet that resumed it last: where its slice hands back

    def __repr__(self) -> str:
        return f"<thread {self.name} {self.state}>"

    @property
    def alive(self) -> bool:
        return self.state in ("new", "running")


class Scheduler:
    """The threads of one run (Machine.state.threads) and which of them runs now (None: the main program)."""

    def __init__(self, machine, compiler) -> None:
        self.machine, self.compiler = machine, compiler
        self.current: URThread | None = None
        self.threads: list[URThread] = []
        self.limit = machine.step_limit  # the run's step limit (a slice runs with a lower one)

    # --- the program's side -------------------------------------------------------------------
    def start(self, routine, where: str) -> URThread:
        machine = self.machine
        if machine.watching is None:  # no switching device: the threads still run, at the e-Series frame
            from codegen.dialects.core.watch import Watching

            machine.watching = Watching(machine, STEP_TIME_S)
        thread = URThread(self, routine, self.current, where)
        if self.current is not None:
            self.current.children.append(thread)
        self.threads.append(thread)
        thread.watcher = machine.watching.watch(WATCH_NAME, "every", lambda t, _pose: self.frame(thread, t))
        return thread

    def frame(self, thread: URThread, t: float) -> None:
        """The core's watcher at cycle t: the thread's slice (unless it sleeps or has ended)."""
        if thread.alive and t >= thread.wake - 1e-9:
            self.resume(thread)
            if not thread.alive:
                self.drop(thread)

    def resume(self, thread: URThread) -> None:
        """Run the thread until it gives up its frame (sync, sleep), ends, or is unwound (killed)."""
        machine = self.machine
        previous, self.current = self.current, thread
        limit = machine.step_limit
        if thread.state != "killed":
            machine.step_limit = min(limit, machine.steps + THREAD_FRAME_STEPS)
        try:
            thread.caller = getcurrent()
            if thread.glet is None:
                thread.state = "running" if thread.state == "new" else thread.state
                thread.glet = greenlet(lambda: self._body(thread), parent=thread.caller)
            elif not thread.glet.dead:
                thread.glet.parent = thread.caller  # where it returns when it ends
            if not thread.glet.dead:
                thread.glet.switch()
        finally:
            machine.step_limit = limit
            self.current = previous
        if thread.error is not None:
            error, thread.error = thread.error, None
            raise error

    def kill(self, thread: URThread, where: str) -> None:
        if not isinstance(thread, URThread):
            raise RunError(f"{where}: kill takes a thread's handle (what run returned), got {describe(thread)}")
        if thread.state == "killed":
            raise RunError(f"{where}: kill: the thread {thread.name} was killed already (its handle is invalid)")
        watcher = thread.watcher
        if watcher is not None and watcher in self.machine.watching.watchers:
            self.machine.watching.unwatch(watcher)  # its frames up to now first
        self._unwind(thread)

    def join(self, fr, thread: URThread, where: str) -> None:
        if not isinstance(thread, URThread):
            raise RunError(f"{where}: join takes a thread's handle (what run returned), got {describe(thread)}")
        if thread.state == "killed":
            raise RunError(f"{where}: join: the thread {thread.name} was killed (its handle is invalid)")
        if thread is self.current:
            raise RunError(f"{where}: join: the thread {thread.name} would wait for itself")
        while thread.alive:
            fr.m.step(where)
            if self.current is None:
                fr.m.elapse(self.machine.watching.cycle, where)  # the main program waits a frame
            else:
                self.pause(self.current)

    def shutdown(self) -> None:
        """The program ended (or stopped): its threads with it."""
        for thread in list(self.threads):
            if thread.alive:
                self._unwind(thread)

    def drop(self, thread: URThread) -> None:
        """No more frames for the thread (without delivering any: it ended, or the program did)."""
        watching, watcher = self.machine.watching, thread.watcher
        if watcher is not None and watching is not None and watcher in watching.watchers:
            watcher.t_off = self.machine.clock
            watching.watchers.remove(watcher)

    def _unwind(self, thread: URThread) -> None:
        for child in thread.children:
            if child.alive:
                self._unwind(child)
        self.drop(thread)
        if thread is self.current:  # a thread killing itself
            thread.state = "killed"
            raise Killed
        alive = thread.alive
        thread.state = "killed"
        if alive and thread.glet is not None and not thread.glet.dead:
            self.resume(thread)  # it wakes in pause(), raises Killed and ends

    # --- the thread's side -----------------------------------------------------------------------
    def _body(self, thread: URThread) -> None:
        try:
            if thread.state != "killed":
                self.compiler.entry(thread.routine)(Frame(self.machine), [], {}, thread.where)
        except Killed:
            pass
        except StepLimitError as exc:
            thread.error = exc
            if self.machine.steps <= self.limit:  # the slice's limit, not the run's
                where = str(exc).split(": step limit")[0]
                thread.error = RunError(
                    f"{where}: thread {thread.name} ran {THREAD_FRAME_STEPS} statements within one controller "
                    "frame without sync() or sleep(): a thread must give up its frame (URScript manual, thread "
                    "scheduling): the controller stops the program"
                )
        except BaseException as exc:  # handed to the program's side, raised there
            thread.error = exc
        finally:
            if thread.state != "killed":
                thread.state = "done"
        # the greenlet ends here: it returns to its parent, the caller of its last slice

    def pause(self, thread: URThread) -> None:
        """The thread gives up its frame (sync, sleep): the program runs on until the thread's next slice."""
        thread.caller.switch()
        if thread.state == "killed":
            raise Killed


def scheduler(fr) -> Scheduler:
    machine = fr.m
    found = machine.state.threads
    if found is None:
        found = machine.state.threads = Scheduler(machine, machine.program.compiler)
    return found


def current(fr) -> URThread | None:
    """The thread running now, None in the main program."""
    found = fr.m.state.threads
    return None if found is None else found.current


class ThreadStatements:
    """Compiler mixin: `thread name(): ... end`, `run name()`, `kill h`, `join h` (the compiler keeps the
    threads apart from the functions: self.threads; self.thread_runs: each `run`, checked by load())."""

    def s_threaddef(self, node):
        name_token, params_node, body = node.children
        name = str(name_token)
        if params_node is not None:
            self.fail(params_node, f"thread {name}: a thread cannot take parameters (URScript manual, threads)")
        if name in self.threads or name in self.routines:
            self.fail(name_token, f"{name} is defined twice")
        routine = Routine(name, [], None, None, self.line(node))
        self.threads[name] = routine
        self.compile_routine_body(routine, body.children)
        return lambda fr: None  # defined at compile time

    def e_run_thread(self, node):
        name_token, args_node = node.children
        name = str(name_token)
        if args_node is not None:
            self.fail(args_node, f"run {name}(): a thread takes no arguments (URScript manual, threads)")
        self.thread_runs.append((name, name_token))
        where = self.where(node)

        def run(fr):
            return scheduler(fr).start(self.threads[name], where)

        return run

    def s_kill_stmt(self, node):
        handle, where = self.expr(node.children[0]), self.where(node)

        def run(fr):
            scheduler(fr).kill(handle(fr), where)

        return run

    def s_join_stmt(self, node):
        handle, where = self.expr(node.children[0]), self.where(node)

        def run(fr):
            scheduler(fr).join(fr, handle(fr), where)

        return run

    def check_thread_runs(self) -> None:
        for thread, token in self.thread_runs:
            if thread not in self.threads:
                what = "a function, not a thread" if thread in self.routines else "not defined"
                self.fail(token, f"run {thread}(): {thread} is {what}")


def ending_threads(rest):
    """The program's body, after which (or at its stop) its threads end."""

    def body(fr):
        try:
            return rest(fr)
        finally:
            running = fr.m.state.threads
            if running is not None:
                running.shutdown()

    return body
