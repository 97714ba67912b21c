// rtusim node L1: a read-only, non-blocking, set-associative cache. The RTL side of the node L1
// timing spec v2, which the C++ L1Cache (sim/mem/l1_cache.h) implements too; its tag store is
// the behavioural SetAssocCache's (sim/cache/set_assoc_cache.h, BasicSetAssocCache<LruPolicy |
// TreePlruPolicy>): fed the same lookups in the same order, both make the same hit/miss decisions.
//
// No data is stored: the simulator needs only timing and the hit/miss state, so the cache keeps
// tags, valid bits, replacement state and MSHRs ({FREE, SEND, WAIT} and a line each). It keeps
// no list of the requests waiting on an MSHR: the outcome outputs say which MSHR a miss waits
// on, the fill outputs say which MSHR a fill frees, and the requester keeps the lists.
//
// Replacement (POLICY): 0 = true LRU, 1 = tree-PLRU, each choosing exactly the victim the C++
// policy chooses (sim/cache/policy/lru_policy.h, tree_plru_policy.h):
//  - Invalid ways are filled first, lowest way first (there is no invalidation).
//  - LRU keeps, per way, its age rank (0 = most recent .. WAYS-1 = least recent); a touch of way w
//    makes it 0 and ages every way younger than w by one. Reset ranks are way w = w, a
//    permutation; valid ways (0 .. v-1) always hold ranks 0 .. v-1, so once every way of a set is
//    valid (the only time a victim is chosen) the ranks order the ways by their last touch, as
//    the C++ timestamps do. Victim: rank WAYS-1.
//  - Tree-PLRU keeps WAYS-1 bits per set, bit n = heap node n (root 1, children 2n and 2n+1,
//    way w = leaf WAYS+w); bit 0 of the row is unused. Touch: every bit on the path to the way
//    points away from it (1 where the path goes left, 0 where it goes right). Victim: follow the
//    bits from the root (0 = left). Reset: all bits 0.
//
// Timing. One clock; "edge" = rising edge of clk; cycle c is the cycle that edge c+1 ends. A
// request offered (i_req_valid) in cycle c is *looked up in cycle c*: the lookup outputs are
// combinational on i_req_addr, i_resp_ready and the state, and the request is *accepted* at the
// edge ending cycle c when o_req_ready is high. All of its effects happen at that edge.
//  - Lookup, in priority order:
//      merged  (o_req_merged = 1): an MSHR in SEND or WAIT holds the line; o_req_mshr = it;
//      hit     (o_req_hit = 1):    else the line is in the tags;
//      primary (both 0):           else an MSHR is FREE; o_req_mshr = the lowest FREE one;
//      refused (o_req_ready = 0):  else (every MSHR busy). Also refused: a hit while the
//                                  response output holds a hit that i_resp_ready refuses, and
//                                  everything while rst_n is low. Merges and primaries never
//                                  wait for the response output.
//    The outcome outputs are meaningful when i_req_valid && o_req_ready.
//  - Tag access at acceptance, exactly one per accepted request (hits, merges and primaries
//    alike: SetAssocCache::access): the line is present: its way is touched; else the victim
//    (lowest invalid way, else the policy's victim) gets the line and is touched. So a primary
//    miss installs its line at once (allocate on miss), and a merge whose pending line was
//    evicted in the meantime installs it again. At most one replacement update per edge.
//  - MSHR at acceptance of a primary: o_req_mshr goes FREE -> SEND with the line.
//  - Hit response: o_resp_valid / o_resp_id HIT_LATENCY cycles after acceptance (a hit looked up
//    in cycle c is on the output in cycle c + HIT_LATENCY), taken at an edge with i_resp_ready.
//    Back-pressure: while the output holds a hit that i_resp_ready refuses, the whole hit pipe
//    holds and hits are refused (simple, not bubble-collapsing; the rtl tier is always ready).
//  - Memory request: the lowest MSHR in SEND drives o_mem_req_valid / o_mem_req_addr (the line's
//    first byte) and goes SEND -> WAIT at an edge with i_mem_req_ready. With an always-ready
//    memory, a primary looked up in cycle c requests in cycle c + 1, one per cycle.
//  - Fill: i_mem_resp_valid / i_mem_resp_addr (any byte of the line) driven during a cycle F: the
//    MSHR in WAIT holding the line shows combinationally on o_fill_valid / o_fill_mshr, and is
//    FREE from the edge ending cycle F. A lookup in cycle F still sees it busy (a lookup of its
//    line merges into it, a primary cannot have it); a lookup in cycle F + 1 sees it free and the
//    line as a hit (unless evicted). A fill changes no tag or replacement state, so fills and
//    lookups never compete: one lookup and one fill per cycle. A fill matching no MSHR in WAIT
//    is ignored (o_fill_valid low).
//  - o_mshrs_busy: MSHRs not FREE.
//
// Reset: synchronous, active low (rst_n): every line invalid, replacement state reset, MSHRs
// FREE, hit pipe empty. Addresses are byte addresses; the cache works on whole lines.
module l1_cache #(
  parameter int ADDR_W      = 48,    // byte address width
  parameter int ID_W        = 16,    // request id width
  parameter int SIZE_BYTES  = 8192,  // capacity; SIZE_BYTES / (LINE_BYTES * WAYS) sets, >= 2
  parameter int WAYS        = 4,     // >= 2; a power of two for tree-PLRU
  parameter int LINE_BYTES  = 64,    // a power of two >= 4
  parameter int POLICY      = 0,     // 0 = lru, 1 = tree-plru
  parameter int MSHRS       = 8,     // outstanding primary misses, >= 2
  parameter int HIT_LATENCY = 1      // cycles from acceptance to a hit's response, >= 1
) (
  input  logic                       clk,
  input  logic                       rst_n,
  // Requests: one line lookup each, and its outcome in the cycle it is looked up.
  input  logic                       i_req_valid,
  output logic                       o_req_ready,
  input  logic [ADDR_W-1:0]          i_req_addr,
  input  logic [ID_W-1:0]            i_req_id,
  output logic                       o_req_hit,
  output logic                       o_req_merged,
  output logic [$clog2(MSHRS)-1:0]   o_req_mshr,
  // Hit responses.
  output logic                       o_resp_valid,
  input  logic                       i_resp_ready,
  output logic [ID_W-1:0]            o_resp_id,
  // Line reads to memory (one per primary miss).
  output logic                       o_mem_req_valid,
  input  logic                       i_mem_req_ready,
  output logic [ADDR_W-1:0]          o_mem_req_addr,
  // Fills from memory (always taken), and the MSHR each frees.
  input  logic                       i_mem_resp_valid,
  input  logic [ADDR_W-1:0]          i_mem_resp_addr,
  output logic                       o_fill_valid,
  output logic [$clog2(MSHRS)-1:0]   o_fill_mshr,
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
  localparam int BUSY_W = $clog2(MSHRS + 1);
  localparam int REPL_W = POLICY == 0 ? WAYS * WAY_W : WAYS;  // replacement state per set

  // Parameter checks at elaboration.
  if (SETS < 2 || SETS * LINE_BYTES * WAYS != SIZE_BYTES || (1 << IDX_W) != SETS)
    $error("l1_cache: SIZE_BYTES / (LINE_BYTES * WAYS) must be a power of two >= 2");
  if (WAYS < 2 || (POLICY == 1 && (1 << WAY_W) != WAYS))
    $error("l1_cache: WAYS must be >= 2, and a power of two for tree-PLRU");
  if (LINE_BYTES < 4 || (1 << OFF_W) != LINE_BYTES)
    $error("l1_cache: LINE_BYTES must be a power of two >= 4");
  if (POLICY != 0 && POLICY != 1) $error("l1_cache: POLICY must be 0 (lru) or 1 (tree-plru)");
  if (MSHRS < 2 || HIT_LATENCY < 1) $error("l1_cache: MSHRS >= 2, HIT_LATENCY >= 1");

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

  typedef enum logic [1:0] {M_FREE, M_SEND, M_WAIT} mshr_state_t;
  mshr_state_t       ms_state_q [MSHRS];
  logic [LINE_W-1:0] ms_line_q  [MSHRS];

  logic              hp_valid_q [HIT_LATENCY];  // hit pipe; the last stage is the output
  logic [ID_W-1:0]   hp_id_q    [HIT_LATENCY];

  // ---- Lookup (combinational) ---------------------------------------------------------------

  logic [LINE_W-1:0] lk_line;
  logic [IDX_W-1:0]  lk_set;
  logic [TAG_W-1:0]  lk_tag;
  assign lk_line = i_req_addr[ADDR_W-1:OFF_W];
  assign lk_set  = lk_line[IDX_W-1:0];
  assign lk_tag  = lk_line[LINE_W-1:IDX_W];

  // Tags: the way holding the line, else the way a tag access would install it into.
  logic             lk_present, lk_any_invalid;
  logic [WAY_W-1:0] lk_way, lk_invalid_way, lk_access_way;
  always_comb begin
    lk_present     = 1'b0;
    lk_way         = '0;
    lk_any_invalid = 1'b0;
    lk_invalid_way = '0;
    for (int w = WAYS - 1; w >= 0; w--) begin
      if (valid_q[lk_set][w] && tag_q[lk_set][w] == lk_tag) begin
        lk_present = 1'b1;
        lk_way     = WAY_W'(w);
      end
      if (!valid_q[lk_set][w]) begin
        lk_any_invalid = 1'b1;
        lk_invalid_way = WAY_W'(w);
      end
    end
    if (lk_present)          lk_access_way = lk_way;
    else if (lk_any_invalid) lk_access_way = lk_invalid_way;
    else                     lk_access_way = repl_victim(repl_q[lk_set]);
  end

  // MSHRs: a busy one holding the line, and the lowest free one.
  logic              lk_pending, have_free;
  logic [MSHR_W-1:0] lk_mshr, free_mshr;
  always_comb begin
    lk_pending = 1'b0;
    lk_mshr    = '0;
    have_free  = 1'b0;
    free_mshr  = '0;
    for (int m = MSHRS - 1; m >= 0; m--) begin
      if (ms_state_q[m] != M_FREE && ms_line_q[m] == lk_line) begin
        lk_pending = 1'b1;
        lk_mshr    = MSHR_W'(m);
      end
      if (ms_state_q[m] == M_FREE) begin
        have_free = 1'b1;
        free_mshr = MSHR_W'(m);
      end
    end
  end

  logic resp_hold;  // the output holds a hit that is not taken: the pipe stands still
  assign resp_hold = o_resp_valid && !i_resp_ready;

  assign o_req_merged = lk_pending;
  assign o_req_hit    = !lk_pending && lk_present;
  assign o_req_mshr   = lk_pending ? lk_mshr : free_mshr;
  always_comb begin
    if (!rst_n)          o_req_ready = 1'b0;
    else if (lk_pending) o_req_ready = 1'b1;
    else if (lk_present) o_req_ready = !resp_hold;
    else                 o_req_ready = have_free;
  end

  logic acc, acc_hit, acc_primary;
  assign acc         = i_req_valid && o_req_ready;
  assign acc_hit     = acc && o_req_hit;
  assign acc_primary = acc && !lk_pending && !lk_present;

  // ---- Memory request: the lowest MSHR waiting to send ---------------------------------------

  logic              send_any;
  logic [MSHR_W-1:0] send_mshr;
  always_comb begin
    send_any  = 1'b0;
    send_mshr = '0;
    for (int m = MSHRS - 1; m >= 0; m--)
      if (ms_state_q[m] == M_SEND) begin
        send_any  = 1'b1;
        send_mshr = MSHR_W'(m);
      end
  end
  assign o_mem_req_valid = send_any;
  assign o_mem_req_addr  = {ms_line_q[send_mshr], OFF_W'(0)};

  // ---- Fill: the waiting MSHR it frees ------------------------------------------------------

  logic [LINE_W-1:0] f_line;
  logic              f_match;
  assign f_line = i_mem_resp_addr[ADDR_W-1:OFF_W];
  always_comb begin
    f_match     = 1'b0;
    o_fill_mshr = '0;
    for (int m = MSHRS - 1; m >= 0; m--)
      if (ms_state_q[m] == M_WAIT && ms_line_q[m] == f_line) begin
        f_match     = 1'b1;
        o_fill_mshr = MSHR_W'(m);
      end
  end
  assign o_fill_valid = i_mem_resp_valid && f_match;

  // ---- Tags and replacement state: one tag access per accepted request ----------------------

  always_ff @(posedge clk) begin
    if (!rst_n) begin
      for (int s = 0; s < SETS; s++) begin
        valid_q[s] <= '0;
        repl_q[s]  <= repl_reset_row();
      end
    end else if (acc) begin
      repl_q[lk_set] <= repl_touch(repl_q[lk_set], lk_access_way);
      if (!lk_present) begin
        valid_q[lk_set][lk_access_way] <= 1'b1;
        tag_q[lk_set][lk_access_way]   <= lk_tag;
      end
    end
  end

  // ---- MSHRs: allocate at a primary, send, free at the fill --------------------------------

  always_ff @(posedge clk) begin
    if (!rst_n) begin
      for (int m = 0; m < MSHRS; m++) ms_state_q[m] <= M_FREE;
    end else begin
      if (acc_primary) begin
        ms_state_q[free_mshr] <= M_SEND;
        ms_line_q[free_mshr]  <= lk_line;
      end
      if (send_any && i_mem_req_ready) ms_state_q[send_mshr] <= M_WAIT;
      if (o_fill_valid) ms_state_q[o_fill_mshr] <= M_FREE;
    end
  end

  always_comb begin
    o_mshrs_busy = '0;
    for (int m = 0; m < MSHRS; m++)
      o_mshrs_busy = o_mshrs_busy + BUSY_W'(ms_state_q[m] != M_FREE);
  end

  // ---- Hit responses: a HIT_LATENCY-stage pipe that holds while its output is refused -------

  always_ff @(posedge clk) begin
    if (!rst_n) begin
      for (int s = 0; s < HIT_LATENCY; s++) hp_valid_q[s] <= 1'b0;
    end else if (!resp_hold) begin
      hp_valid_q[0] <= acc_hit;
      hp_id_q[0]    <= i_req_id;
      for (int s = 1; s < HIT_LATENCY; s++) begin
        hp_valid_q[s] <= hp_valid_q[s-1];
        hp_id_q[s]    <= hp_id_q[s-1];
      end
    end
  end
  assign o_resp_valid = hp_valid_q[HIT_LATENCY-1];
  assign o_resp_id    = hp_id_q[HIT_LATENCY-1];

  // Offset bits of the addresses select nothing: the cache works on whole lines.
  logic unused_offsets;
  assign unused_offsets = ^{i_req_addr[OFF_W-1:0], i_mem_resp_addr[OFF_W-1:0]};
endmodule
