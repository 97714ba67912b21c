// rtusim node L1: a read-only, non-blocking, set-associative cache (RTL twin of the C++
// behavioural model sim/cache/set_assoc_cache.h, BasicSetAssocCache<LruPolicy|TreePlruPolicy>).
//
// No data is stored: the simulator needs only timing and the hit/miss state, so the cache keeps
// tags, valid bits, replacement state and MSHRs, and a response carries the request id and its
// outcome class (hit, primary miss, merged secondary miss), never line data.
//
// Replacement (POLICY): 0 = true LRU, 1 = tree-PLRU, each choosing exactly the victim the C++
// policy chooses (sim/cache/policy/lru_policy.h, tree_plru_policy.h):
//  - Invalid ways are filled first, lowest way first (there is no invalidation).
//  - LRU keeps, per way, its age rank (0 = most recent .. WAYS-1 = least recent); a touch of way w
//    makes it 0 and ages every way younger than w by one. Reset ranks are way w = w, a
//    permutation; once every way of a set has been filled (the only time a victim is chosen) the
//    ranks order the ways by their last touch, as the C++ timestamps do. Victim: rank WAYS-1.
//  - Tree-PLRU keeps WAYS-1 bits per set, bit n = heap node n (root 1, children 2n and 2n+1,
//    way w = leaf WAYS+w); bit 0 of the row is unused. Touch: every bit on the path to the way
//    points away from it (1 where the path goes left, 0 where it goes right). Victim: follow the
//    bits from the root (0 = left). Reset: all bits 0.
//
// Timing (one clock; "edge" = rising edge of clk; a request "is accepted at edge e" when
// i_req_valid && o_req_ready are high in the cycle that edge ends):
//  - Lookup at acceptance. o_req_ready is combinational on i_req_addr: the tag compare and the MSHR
//    compare are done on the state before edge e, and the request's effect happens at edge e:
//      hit            : the way is touched in the replacement state at edge e; the response is
//                       valid HIT_LATENCY cycles after edge e (HIT_LATENCY >= 1; with
//                       HIT_LATENCY = 1 in the cycle right after acceptance), unless the response
//                       queue is backed up by i_resp_ready.
//      primary miss   : (line neither present nor in an MSHR) an MSHR is allocated at edge e; no
//                       tag or replacement state changes. o_mem_req_valid is high from the cycle
//                       after edge e (lowest-index MSHR waiting to send first).
//      secondary miss : (line in an MSHR that has not been filled yet) the request id is
//                       appended to that MSHR's targets; no memory request, no state change.
//  - Fill at fill response. In a cycle with i_mem_resp_valid high the fill takes the tag array:
//    o_req_ready is low, and at the end of that cycle the line is installed (victim chosen then:
//    lowest invalid way, else the policy's victim on the state at that moment) and touched once,
//    and its MSHR starts draining. Merged requests do not touch again (a second touch of the
//    most recent way changes neither policy's state). A fill that matches no waiting MSHR is
//    ignored. So at most one replacement update happens per edge: a hit's or a fill's.
//  - Drain: each cycle the lowest-index draining MSHR moves one target (primary first, then the
//    merged ones in arrival order) into the response queue; it is free the cycle after its last.
//  - Latencies with an always-ready response port: a hit is answered HIT_LATENCY cycles after
//    acceptance; a primary miss L + 3 cycles after acceptance when memory accepts the fill request
//    at once and raises i_mem_resp_valid L cycles after accepting it (1 cycle to issue, L, the
//    fill edge, 1 drain cycle); a merged miss k cycles after its primary (k-th merged target).
//  - Stalls (o_req_ready low): in reset; in a fill cycle; a hit without a free response credit
//    (RESP_DEPTH entries shared by the queue and the hits in the latency pipe); a secondary miss
//    whose MSHR already holds TARGETS targets; a primary miss with every MSHR busy (an MSHR is
//    busy from allocation until its last target drains). Hits and merges go on under full MSHRs.
//  - Responses leave in queue order: o_resp_valid while the queue is non-empty, popped when
//    i_resp_ready is high.
//
// Reset: synchronous, active low (rst_n): every line invalid, replacement state reset, MSHRs and
// queues empty. Addresses are byte addresses; a memory request carries the line's first byte.
module l1_cache #(
  parameter int ADDR_W      = 48,    // byte address width
  parameter int ID_W        = 16,    // request id width
  parameter int SIZE_BYTES  = 8192,  // capacity; SIZE_BYTES / (LINE_BYTES * WAYS) sets, >= 2
  parameter int WAYS        = 4,     // >= 2; a power of two for tree-PLRU
  parameter int LINE_BYTES  = 64,    // a power of two >= 4
  parameter int POLICY      = 0,     // 0 = lru, 1 = tree-plru
  parameter int MSHRS       = 8,     // >= 2
  parameter int TARGETS     = 8,     // requests per MSHR (the primary included), >= 1
  parameter int HIT_LATENCY = 1,     // cycles from acceptance to the response of a hit, >= 1
  parameter int RESP_DEPTH  = 4      // response queue entries, >= 1
) (
  input  logic              clk,
  input  logic              rst_n,
  // Requests: one line lookup each.
  input  logic              i_req_valid,
  output logic              o_req_ready,
  input  logic [ADDR_W-1:0] i_req_addr,
  input  logic [ID_W-1:0]   i_req_id,
  // Responses: id and outcome (hit; else merged = 1 for a secondary miss, 0 for a primary one).
  output logic              o_resp_valid,
  input  logic              i_resp_ready,
  output logic [ID_W-1:0]   o_resp_id,
  output logic              o_resp_hit,
  output logic              o_resp_merged,
  // Fill requests to memory (one per primary miss).
  output logic              o_mem_req_valid,
  input  logic              i_mem_req_ready,
  output logic [ADDR_W-1:0] o_mem_req_addr,
  // Fill responses from memory (always accepted; any address within the line).
  input  logic              i_mem_resp_valid,
  input  logic [ADDR_W-1:0] i_mem_resp_addr,
  // Status: MSHRs busy.
  output logic [$clog2(MSHRS+1)-1:0] o_mshrs_busy
);
  localparam int SETS   = SIZE_BYTES / (LINE_BYTES * WAYS);
  localparam int OFF_W  = $clog2(LINE_BYTES);
  localparam int IDX_W  = $clog2(SETS);
  localparam int LINE_W = ADDR_W - OFF_W;
  localparam int TAG_W  = LINE_W - IDX_W;
  localparam int WAY_W  = $clog2(WAYS);
  localparam int MSHR_W = $clog2(MSHRS);
  localparam int TGT_W  = $clog2(TARGETS + 1);
  localparam int TIDX_W = TARGETS > 1 ? $clog2(TARGETS) : 1;
  localparam int RQ_W   = $clog2(RESP_DEPTH + 1);
  localparam int PTR_W  = RESP_DEPTH > 1 ? $clog2(RESP_DEPTH) : 1;
  localparam int REPL_W = POLICY == 0 ? WAYS * WAY_W : WAYS;  // replacement state per set
  localparam int PIPE   = HIT_LATENCY - 1;                      // hit delay stages before the queue

  // Parameter checks at elaboration.
  if (SETS < 2 || SETS * LINE_BYTES * WAYS != SIZE_BYTES || (1 << IDX_W) != SETS)
    $error("l1_cache: SIZE_BYTES / (LINE_BYTES * WAYS) must be a power of two >= 2");
  if (WAYS < 2 || (POLICY == 1 && (1 << WAY_W) != WAYS))
    $error("l1_cache: WAYS must be >= 2, and a power of two for tree-PLRU");
  if (LINE_BYTES < 4 || (1 << OFF_W) != LINE_BYTES)
    $error("l1_cache: LINE_BYTES must be a power of two >= 4");
  if (POLICY != 0 && POLICY != 1) $error("l1_cache: POLICY must be 0 (lru) or 1 (tree-plru)");
  if (MSHRS < 2 || TARGETS < 1 || HIT_LATENCY < 1 || RESP_DEPTH < 1)
    $error("l1_cache: MSHRS >= 2, TARGETS >= 1, HIT_LATENCY >= 1, RESP_DEPTH >= 1");

  // ---- Replacement policy: pure functions of one set's state row ----------------------------

  function automatic logic [REPL_W-1:0] repl_reset_row();
    logic [REPL_W-1:0] row = '0;
    if (POLICY == 0)
      for (int w = 0; w < WAYS; w++) row[w*WAY_W +: WAY_W] = WAY_W'(w);
    return row;
  endfunction

  function automatic logic [REPL_W-1:0] repl_touch(logic [REPL_W-1:0] row, logic [WAY_W-1:0] way);
    logic [REPL_W-1:0] next = row;
    if (POLICY == 0) begin
      logic [WAY_W-1:0] rank = row[way*WAY_W +: WAY_W];
      for (int w = 0; w < WAYS; w++)
        if (WAY_W'(w) == way) next[w*WAY_W +: WAY_W] = '0;
        else if (row[w*WAY_W +: WAY_W] < rank)
          next[w*WAY_W +: WAY_W] = row[w*WAY_W +: WAY_W] + 1'b1;
    end else begin
      int node = 1;
      for (int level = WAY_W - 1; level >= 0; level--) begin
        next[node] = ~way[level];  // point at the other half
        node = 2 * node + int'(way[level]);
      end
    end
    return next;
  endfunction

  function automatic logic [WAY_W-1:0] repl_victim(logic [REPL_W-1:0] row);
    logic [WAY_W-1:0] victim = '0;
    if (POLICY == 0) begin
      for (int w = 0; w < WAYS; w++)
        if (row[w*WAY_W +: WAY_W] == WAY_W'(WAYS - 1)) victim = WAY_W'(w);
    end else begin
      int node = 1;
      for (int level = 0; level < WAY_W; level++) node = 2 * node + int'(row[node]);
      victim = WAY_W'(node - WAYS);
    end
    return victim;
  endfunction

  // ---- State --------------------------------------------------------------------------------

  logic [WAYS-1:0]   valid_q [SETS];
  logic [TAG_W-1:0]  tag_q   [SETS][WAYS];
  logic [REPL_W-1:0] repl_q  [SETS];

  typedef enum logic [1:0] {M_FREE, M_SEND, M_WAIT, M_DRAIN} mshr_state_t;
  mshr_state_t       ms_state_q [MSHRS];
  logic [LINE_W-1:0] ms_line_q  [MSHRS];
  logic [ID_W-1:0]   ms_tgt_q   [MSHRS][TARGETS];  // target 0 is the primary miss
  logic [TGT_W-1:0]  ms_cnt_q   [MSHRS];           // targets held
  logic [TGT_W-1:0]  ms_head_q  [MSHRS];           // next target to drain

  localparam int RQ_E = ID_W + 2;  // {hit, merged, id}
  logic [RQ_E-1:0]  rq_q [RESP_DEPTH];
  logic [PTR_W-1:0] rq_head_q, rq_tail_q;
  logic [RQ_W-1:0]  rq_count_q;

  // ---- Lookup of the request (combinational) ------------------------------------------------

  logic [IDX_W-1:0]  lk_set;
  logic [TAG_W-1:0]  lk_tag;
  logic [LINE_W-1:0] lk_line;
  assign lk_line = i_req_addr[ADDR_W-1:OFF_W];
  assign lk_set  = lk_line[IDX_W-1:0];
  assign lk_tag  = lk_line[LINE_W-1:IDX_W];

  logic             lk_hit;
  logic [WAY_W-1:0] lk_way;
  always_comb begin
    lk_hit = 1'b0;
    lk_way = '0;
    for (int w = 0; w < WAYS; w++)
      if (valid_q[lk_set][w] && tag_q[lk_set][w] == lk_tag) begin
        lk_hit = 1'b1;
        lk_way = WAY_W'(w);
      end
  end

  // MSHR search: a pending (not yet filled) MSHR for the line, and the lowest free one.
  logic              lk_pending, have_free;
  logic [MSHR_W-1:0] lk_mshr, free_mshr;
  always_comb begin
    lk_pending = 1'b0;
    lk_mshr    = '0;
    have_free  = 1'b0;
    free_mshr  = '0;
    for (int m = MSHRS - 1; m >= 0; m--) begin
      if ((ms_state_q[m] == M_SEND || ms_state_q[m] == M_WAIT) && ms_line_q[m] == lk_line) begin
        lk_pending = 1'b1;
        lk_mshr    = MSHR_W'(m);
      end
      if (ms_state_q[m] == M_FREE) begin
        have_free = 1'b1;
        free_mshr = MSHR_W'(m);
      end
    end
  end

  // ---- Fill (combinational): the waiting MSHR it completes, and the way it installs into ----

  logic [LINE_W-1:0] f_line;
  logic [IDX_W-1:0]  f_set;
  logic              f_match;
  logic [MSHR_W-1:0] f_mshr;
  logic [WAY_W-1:0]  f_way;
  logic              f_any_invalid;
  assign f_line = i_mem_resp_addr[ADDR_W-1:OFF_W];
  assign f_set  = f_line[IDX_W-1:0];
  always_comb begin
    f_match = 1'b0;
    f_mshr  = '0;
    for (int m = MSHRS - 1; m >= 0; m--)
      if (ms_state_q[m] == M_WAIT && ms_line_q[m] == f_line) begin
        f_match = 1'b1;
        f_mshr  = MSHR_W'(m);
      end
    f_any_invalid = 1'b0;
    f_way = '0;
    for (int w = WAYS - 1; w >= 0; w--)
      if (!valid_q[f_set][w]) begin
        f_any_invalid = 1'b1;
        f_way = WAY_W'(w);
      end
    if (!f_any_invalid) f_way = repl_victim(repl_q[f_set]);
  end
  logic fill;
  assign fill = i_mem_resp_valid && f_match;

  // ---- Memory request and drain selection ---------------------------------------------------

  logic              send_any, drain_any;
  logic [MSHR_W-1:0] send_mshr, drain_mshr;
  always_comb begin
    send_any   = 1'b0;
    send_mshr  = '0;
    drain_any  = 1'b0;
    drain_mshr = '0;
    for (int m = MSHRS - 1; m >= 0; m--) begin
      if (ms_state_q[m] == M_SEND) begin
        send_any  = 1'b1;
        send_mshr = MSHR_W'(m);
      end
      if (ms_state_q[m] == M_DRAIN) begin
        drain_any  = 1'b1;
        drain_mshr = MSHR_W'(m);
      end
    end
  end
  assign o_mem_req_valid = send_any;
  assign o_mem_req_addr  = {ms_line_q[send_mshr], OFF_W'(0)};

  // ---- Hit latency pipe and response credits ------------------------------------------------

  logic            hit_push;       // a hit enters the response queue at this edge
  logic [ID_W-1:0] hit_push_id;
  logic [RQ_W-1:0] pipe_count;     // hits in the pipe, each holding a queue credit
  logic            acc, acc_hit;

  logic [RQ_W:0] occupancy;
  logic          drain_push, hit_credit;
  assign occupancy  = {1'b0, rq_count_q} + {1'b0, pipe_count};
  assign drain_push = drain_any && occupancy < (RQ_W + 1)'(RESP_DEPTH);
  assign hit_credit = occupancy + {{RQ_W{1'b0}}, drain_push} < (RQ_W + 1)'(RESP_DEPTH);

  if (PIPE == 0) begin : g_no_pipe
    assign hit_push    = acc_hit;
    assign hit_push_id = i_req_id;
    assign pipe_count  = '0;
  end else begin : g_pipe
    logic            hp_v_q  [PIPE];
    logic [ID_W-1:0] hp_id_q [PIPE];
    always_ff @(posedge clk) begin
      if (!rst_n) begin
        for (int s = 0; s < PIPE; s++) hp_v_q[s] <= 1'b0;
      end else begin
        hp_v_q[0]  <= acc_hit;
        hp_id_q[0] <= i_req_id;
        for (int s = 1; s < PIPE; s++) begin
          hp_v_q[s]  <= hp_v_q[s-1];
          hp_id_q[s] <= hp_id_q[s-1];
        end
      end
    end
    always_comb begin
      pipe_count = '0;
      for (int s = 0; s < PIPE; s++) pipe_count = pipe_count + {{(RQ_W-1){1'b0}}, hp_v_q[s]};
    end
    assign hit_push    = hp_v_q[PIPE-1];
    assign hit_push_id = hp_id_q[PIPE-1];
  end

  // ---- Request acceptance -------------------------------------------------------------------

  always_comb begin
    if (!rst_n || i_mem_resp_valid) o_req_ready = 1'b0;
    else if (lk_hit)                o_req_ready = hit_credit;
    else if (lk_pending)            o_req_ready = ms_cnt_q[lk_mshr] < TGT_W'(TARGETS);
    else                            o_req_ready = have_free;
  end
  assign acc     = i_req_valid && o_req_ready;
  assign acc_hit = acc && lk_hit;

  // ---- Responses ----------------------------------------------------------------------------

  function automatic logic [PTR_W-1:0] rq_next(logic [PTR_W-1:0] p);
    return p == PTR_W'(RESP_DEPTH - 1) ? '0 : p + 1'b1;
  endfunction

  logic pop;
  assign o_resp_valid  = rq_count_q != '0;
  assign pop           = o_resp_valid && i_resp_ready;
  assign o_resp_hit    = rq_q[rq_head_q][ID_W+1];
  assign o_resp_merged = rq_q[rq_head_q][ID_W];
  assign o_resp_id     = rq_q[rq_head_q][ID_W-1:0];

  logic [RQ_E-1:0] drain_entry;
  assign drain_entry = {1'b0, ms_head_q[drain_mshr] != '0,
                        ms_tgt_q[drain_mshr][ms_head_q[drain_mshr][TIDX_W-1:0]]};

  always_ff @(posedge clk) begin
    if (!rst_n) begin
      rq_head_q  <= '0;
      rq_tail_q  <= '0;
      rq_count_q <= '0;
    end else begin
      if (hit_push) rq_q[rq_tail_q] <= {1'b1, 1'b0, hit_push_id};
      if (drain_push) rq_q[hit_push ? rq_next(rq_tail_q) : rq_tail_q] <= drain_entry;
      case ({hit_push, drain_push})
        2'b11:   rq_tail_q <= rq_next(rq_next(rq_tail_q));
        2'b10, 2'b01: rq_tail_q <= rq_next(rq_tail_q);
        default: ;
      endcase
      if (pop) rq_head_q <= rq_next(rq_head_q);
      rq_count_q <= rq_count_q + RQ_W'(hit_push) + RQ_W'(drain_push) - RQ_W'(pop);
    end
  end

  // ---- Tags and replacement state: one update per edge (a fill's or a hit's) ---------------

  logic [IDX_W-1:0] upd_set;
  logic [WAY_W-1:0] upd_way;
  assign upd_set = fill ? f_set : lk_set;
  assign upd_way = fill ? f_way : lk_way;

  always_ff @(posedge clk) begin
    if (!rst_n) begin
      for (int s = 0; s < SETS; s++) begin
        valid_q[s] <= '0;
        repl_q[s]  <= repl_reset_row();
      end
    end else begin
      if (fill || acc_hit) repl_q[upd_set] <= repl_touch(repl_q[upd_set], upd_way);
      if (fill) begin
        valid_q[f_set][f_way] <= 1'b1;
        tag_q[f_set][f_way]   <= f_line[LINE_W-1:IDX_W];
      end
    end
  end

  // ---- MSHRs --------------------------------------------------------------------------------

  always_ff @(posedge clk) begin
    if (!rst_n) begin
      for (int m = 0; m < MSHRS; m++) begin
        ms_state_q[m] <= M_FREE;
        ms_cnt_q[m]   <= '0;
        ms_head_q[m]  <= '0;
      end
    end else begin
      if (acc && !lk_hit && !lk_pending) begin  // primary miss
        ms_state_q[free_mshr]  <= M_SEND;
        ms_line_q[free_mshr]   <= lk_line;
        ms_tgt_q[free_mshr][0] <= i_req_id;
        ms_cnt_q[free_mshr]    <= TGT_W'(1);
        ms_head_q[free_mshr]   <= '0;
      end
      if (acc && !lk_hit && lk_pending) begin   // secondary miss: merge
        ms_tgt_q[lk_mshr][ms_cnt_q[lk_mshr][TIDX_W-1:0]] <= i_req_id;
        ms_cnt_q[lk_mshr] <= ms_cnt_q[lk_mshr] + 1'b1;
      end
      if (send_any && i_mem_req_ready) ms_state_q[send_mshr] <= M_WAIT;
      if (fill) ms_state_q[f_mshr] <= M_DRAIN;
      if (drain_push) begin
        if (ms_head_q[drain_mshr] + 1'b1 == ms_cnt_q[drain_mshr]) begin
          ms_state_q[drain_mshr] <= M_FREE;
          ms_head_q[drain_mshr]  <= '0;
        end else begin
          ms_head_q[drain_mshr] <= ms_head_q[drain_mshr] + 1'b1;
        end
      end
    end
  end

  always_comb begin
    o_mshrs_busy = '0;
    for (int m = 0; m < MSHRS; m++)
      o_mshrs_busy = o_mshrs_busy + {{($clog2(MSHRS+1)-1){1'b0}}, ms_state_q[m] != M_FREE};
  end

  // Offset bits of the addresses select nothing: the cache works on whole lines.
  logic unused_offsets;
  assign unused_offsets = ^{i_req_addr[OFF_W-1:0], i_mem_resp_addr[OFF_W-1:0]};
endmodule
