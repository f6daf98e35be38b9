// Daemon::Run, relightd's frame loop (daemon.h says how ticks are paced),
// with its steps: waiting for a tick while polling live input, and writing
// the frame to the sinks.
#include <algorithm>

#include "daemon_impl.h"
#include "frame_pacing.h"
#include "relight/base/clock.h"
#include "relight/base/log.h"
#include "startup_memory.h"

namespace relight::daemon {

bool Daemon::Impl::WaitForTick(int64_t t0_us, int64_t deadline_us, const RenderBudget& budget,
                               const std::atomic<bool>& stop, const std::atomic<bool>& reload,
                               int64_t* pending_arrival_us) {
  for (;;) {
    const int64_t now = MonotonicUs();
    if (stop.load() || reload.load() || now >= deadline_us) return false;
    const int64_t arrival = PollInputs(now - t0_us, true);
    if (arrival > *pending_arrival_us) *pending_arrival_us = arrival;
    if (*pending_arrival_us > 0 && budget.Allows(now)) return true;
    SleepUntil(std::min(deadline_us, now + 1000));
  }
}

Status Daemon::Impl::WriteSinks(int64_t frame) {
  for (size_t i = 0; i < sinks.size();) {
    const Status st = sinks[i]->Write(pipeline.pixels(), pipeline.width(), pipeline.height(), frame);
    if (!st.ok()) {
      if (frame == 0) return st;
      Log(LogLevel::kError, "relightd: %s: %s; no more frames go there", sinks[i]->Describe().c_str(),
          st.ToString().c_str());
      sinks.erase(sinks.begin() + static_cast<long>(i));
      continue;
    }
    ++i;
  }
  return Status::Ok();
}

Status Daemon::Run(const std::atomic<bool>& stop, std::atomic<bool>& reload) {
  Impl& m = *impl_;
  const int64_t t0_us = MonotonicUs();
  // Live input only (no script plays): the ticks follow the input. A frame
  // rendered early for a live change moves the next tick to one period after
  // it, and the budget lets a change that comes a little before that render
  // at once, so a console sending at the frame rate is shown about one render
  // after each DMX frame instead of waiting for a tick of its own phase.
  // Scripts keep the fixed ticks t0 + k/fps: a replay's frames stay the same.
  const bool follow_input = !m.config.script_time && !m.config.fixed_ticks && m.LiveOnly();
  RenderBudget budget(m.period_us, follow_input);
  int64_t tick = 0;                         // the next tick: script time tick * period
  int64_t next_tick_us = t0_us;             // following live input: when the next tick is due
  int64_t pending_arrival_us = 0;           // newest live change not yet shown
  bool have_frame = false;
  for (int64_t frame = 0; !stop.load(); ++frame) {
    bool early = false;
    // Following live input, ticks keep to the budget too: renders stay at most --fps on average.
    const int64_t deadline_us =
        follow_input ? std::max(next_tick_us, budget.EarliestUs()) : t0_us + tick * m.period_us;
    if (!m.config.script_time) {
      early = m.WaitForTick(t0_us, deadline_us, budget, stop, reload, &pending_arrival_us);
      if (stop.load()) break;
      if (!early && MonotonicUs() < deadline_us) {
        --frame;  // woken for a reload only
        if (reload.exchange(false)) m.Reload();
        RELIGHT_RETURN_IF_ERROR(m.fatal);
        continue;
      }
    }
    if (reload.exchange(false)) m.Reload();
    RELIGHT_RETURN_IF_ERROR(m.fatal);
    // Daemon time: the tick's script time, or now for an early frame or a tick following live input.
    const int64_t start_us = MonotonicUs();
    const int64_t time_us = early || follow_input ? start_us - t0_us : tick * m.period_us;
    if (!early) {
      const int64_t arrival = m.PollInputs(time_us, false);
      if (arrival > pending_arrival_us) pending_arrival_us = arrival;
    }
    // Nothing moved since the last frame: send it again instead of redrawing
    // it -- unless an emitter shows a quick answer, which this frame settles.
    const bool render = m.ApplyFader(time_us) > 0 || !have_frame || m.force_render || !m.engine.emitters_settled();
    m.force_render = false;
    int64_t render_us = 0;
    if (render) {
      const int64_t render_start_us = MonotonicUs();
      budget.Spend(render_start_us);
      RELIGHT_RETURN_IF_ERROR(m.pipeline.Render(m.engine));
      render_us = MonotonicUs() - render_start_us;
      have_frame = true;
      ++m.stats.renders;
      m.stats.render_times.Add(render_us);
      m.stats.update_times.Add(m.pipeline.last_update_us());
      m.stats.draw_times.Add(m.pipeline.last_draw_us());
      m.stats.drawn_triangles = m.pipeline.last_drawn_triangles();
      m.stats.draw_resolved = m.pipeline.last_draw_resolved();
      m.stats.mesh_triangles = m.engine.bake().mesh.triangle_count();
    }
    RELIGHT_RETURN_IF_ERROR(m.WriteSinks(frame));
    const int64_t out_us = MonotonicUs();
    if (render && m.stats.renders == 2 && m.config.release_startup_memory) ReleaseFreeHeapPages();  // frames' leftovers

    const int64_t shown_arrival_us = render ? pending_arrival_us : 0;
    if (shown_arrival_us > 0) {
      const int64_t latency = out_us - shown_arrival_us;
      m.stats.last_latency_us = static_cast<uint32_t>(latency < 0 ? 0 : latency > 0xFFFFFFFF ? 0xFFFFFFFF : latency);
      pending_arrival_us = 0;
    }
    for (const control::BoundInput& in : m.inputs) in.source->OnFrameOut(static_cast<uint32_t>(frame + 1), m.stats.last_latency_us);
    ++m.stats.frames;
    if (early) ++m.stats.early_frames;
    m.stats.render_us_total += render_us;
    if (render_us > m.stats.render_us_max) m.stats.render_us_max = render_us;
    if (m.observer) m.observer({frame, early ? -1 : tick, render_us, out_us, shown_arrival_us});

    if (m.config.max_frames > 0 && frame + 1 >= m.config.max_frames) break;
    if (!early && m.config.exit_when_replay_done && m.ScriptsFinished() && m.path.Idle(time_us)) break;
    if (!early) ++tick;
    if (follow_input) {
      // The next tick one period after this frame; behind schedule: skip, don't queue.
      next_tick_us = start_us + m.period_us;
      if (out_us >= next_tick_us) {
        const int64_t behind = (out_us - next_tick_us) / m.period_us + 1;
        m.stats.ticks_skipped += behind;
        next_tick_us += behind * m.period_us;
      }
    } else if (!early && !m.config.script_time) {
      // Behind schedule: skip to the next tick still ahead rather than queue frames.
      const int64_t due = (out_us - t0_us) / m.period_us + 1;
      if (due > tick) {
        m.stats.ticks_skipped += due - tick;
        tick = due;
      }
    }
  }
  for (const auto& sink : m.sinks) RELIGHT_RETURN_IF_ERROR(sink->Finish());
  return Status::Ok();
}

}  // namespace relight::daemon
