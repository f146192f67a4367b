// The storyboard's elements and their states as esmini runs them (runtime.hpp): Start, End, Stop,
// the state propagated from children to parents, event priorities, and the trigger evaluation
// that opens each step (docs/import.md, "The player's step").

#include <algorithm>

#include "runtime.hpp"

namespace emrm::openscenario::detail {

StoryboardRuntime::StoryboardRuntime(const Scenario& scenario, World& world) : world_(world) { build(scenario); }

StoryboardRuntime::~StoryboardRuntime() = default;

Node* StoryboardRuntime::add(ElementType type, const std::string& name, Node* parent) {
  nodes_.push_back(std::make_unique<Node>());
  Node* node = nodes_.back().get();
  node->type = type;
  node->name = name;
  node->parent = parent;
  if (parent != nullptr) parent->children.push_back(node);
  return node;
}

void StoryboardRuntime::build(const Scenario& scenario) {
  const Storyboard& board = scenario.storyboard;
  for (const Action& action : board.init) init_.push_back(std::make_unique<ActionRuntime>(action, action.actor));
  root_ = add(ElementType::kStory, "Storyboard", nullptr);
  root_->is_storyboard = true;
  if (board.stop) root_->stop_trigger = std::make_unique<TriggerRuntime>(*board.stop);
  for (const Story& story : board.stories) {
    Node* story_node = add(ElementType::kStory, story.name, root_);
    for (const Act& act : story.acts) {
      Node* act_node = add(ElementType::kAct, act.name, story_node);
      if (act.start) act_node->start_trigger = std::make_unique<TriggerRuntime>(*act.start);
      if (act.stop) act_node->stop_trigger = std::make_unique<TriggerRuntime>(*act.stop);
      for (const ManeuverGroup& group : act.groups) {
        Node* group_node = add(ElementType::kManeuverGroup, group.name, act_node);
        group_node->max_executions = group.max_executions;
        for (const Maneuver& maneuver : group.maneuvers) {
          Node* maneuver_node = add(ElementType::kManeuver, maneuver.name, group_node);
          for (const Event& event : maneuver.events) {
            Node* event_node = add(ElementType::kEvent, event.name, maneuver_node);
            event_node->max_executions = event.max_executions;
            event_node->priority = event.priority;
            if (event.start) event_node->start_trigger = std::make_unique<TriggerRuntime>(*event.start);
            for (const Action& action : event.actions) {
              // One action per actor of the group (a Private action names none of its own).
              const bool global = std::holds_alternative<EnvironmentAction>(action.kind) ||
                                  std::holds_alternative<ParameterAction>(action.kind);
              const std::vector<std::string> actors =
                  action.actor.empty() && !global ? group.actors : std::vector<std::string>{action.actor};
              for (const std::string& actor : actors) {
                Node* action_node = add(ElementType::kAction, action.name, event_node);
                action_node->action = std::make_unique<ActionRuntime>(action, actor);
              }
            }
          }
        }
      }
    }
  }
  // Each StoryboardElementStateCondition listens to the elements of its type and name.
  std::vector<TriggerRuntime*> triggers;
  for (const auto& node : nodes_) {
    if (node->start_trigger) triggers.push_back(node->start_trigger.get());
    if (node->stop_trigger) triggers.push_back(node->stop_trigger.get());
  }
  for (TriggerRuntime* trigger : triggers)
    for (auto& group : trigger->groups())
      for (auto& condition : group) {
        const auto* state = std::get_if<StoryboardElementStateCondition>(&condition->spec().kind);
        if (state == nullptr) continue;
        for (const auto& node : nodes_)
          if (!node->is_storyboard && node->type == state->type && node->name == state->ref)
            node->listeners.push_back(condition.get());
      }
}

void StoryboardRuntime::set_state(Node& node, State state, StateTransition transition) {
  node.transition = transition;
  if (node.state == state) return;
  node.state = state;
  if (state == State::kRunning && world_.element_started != nullptr && !node.is_storyboard)
    (*world_.element_started)(world_.time_s, node.name);
  for (ConditionRuntime* listener : node.listeners) listener->notify({state, transition});
}

void StoryboardRuntime::start() {
  for (auto& action : init_) {
    action->set_running(true);
    if (action->start(world_, world_.time_s)) action->set_running(false);
  }
  start(*root_, world_.time_s);
}

void StoryboardRuntime::start(Node& node, double time_s) {
  if (node.type == ElementType::kEvent && !node.is_storyboard) {
    start_event(node, time_s);
    return;
  }
  const bool has_trigger = node.start_trigger != nullptr;
  if (node.state == State::kInit && has_trigger) {
    set_state(node, State::kStandby, StateTransition::kInitToStandby);
  } else if ((node.state == State::kInit && !has_trigger) || node.state == State::kStandby || node.executions > 0) {
    set_state(node, State::kRunning, StateTransition::kStart);
    ++node.executions;
  }
  if (node.state != State::kRunning) return;
  if (node.type == ElementType::kAction) {
    node.action->set_running(true);
    if (node.action->start(world_, time_s)) end(node);
    return;
  }
  for (Node* child : node.children) start(*child, time_s);
}

// esmini's Event::Start: the priority decides whether the event starts, and its actions end the
// running actions of the same entity that control one of the same domains.
void StoryboardRuntime::start_event(Node& event, double time_s) {
  Node& maneuver = *event.parent;
  const bool has_trigger = event.start_trigger != nullptr;
  if (event.state == State::kInit && has_trigger) {
    set_state(event, State::kStandby, StateTransition::kInitToStandby);
    return;
  }
  const auto running = [](const Node* n) { return n->state == State::kRunning; };
  switch (event.priority) {
    case Priority::kOverwrite:
    case Priority::kOverride:
      if (event.state == State::kRunning) return;
      for (Node* sibling : maneuver.children)
        if (sibling != &event && running(sibling)) end(*sibling);
      break;
    case Priority::kSkip:
      if (std::any_of(maneuver.children.begin(), maneuver.children.end(), running)) return;
      break;
    case Priority::kParallel:
      if (event.state == State::kRunning) return;
      break;
  }
  set_state(event, State::kRunning, StateTransition::kStart);
  ++event.executions;
  if (event.children.empty()) {
    end(event);
    return;
  }
  for (Node* action_node : event.children) {
    ActionRuntime& action = *action_node->action;
    for (auto& init : init_)
      if (init->running() && init->actor() == action.actor() && (init->domains() & action.domains()) != 0)
        init->set_running(false);
    for (const auto& other : nodes_)
      if (other->action && other.get() != action_node && other->state == State::kRunning &&
          other->action->actor() == action.actor() && (other->action->domains() & action.domains()) != 0) {
        other->action->set_running(false);
        end(*other);
      }
    action_node->state = State::kInit;  // an action restarts with each execution of its event
    start(*action_node, time_s);
  }
}

void StoryboardRuntime::propagate(Node& node) {
  if (node.is_storyboard || node.state == State::kComplete) return;
  if (std::all_of(node.children.begin(), node.children.end(),
                  [](const Node* c) { return c->state == State::kComplete; }))
    end(node);
}

void StoryboardRuntime::reset(Node& node) {
  for (Node* child : node.children) reset(*child);
  node.state = State::kInit;
  node.transition = StateTransition::kNone;
  if (node.action) node.action->set_running(false);
}

void StoryboardRuntime::end(Node& node) {
  if (node.state == State::kComplete) return;
  for (Node* child : node.children)
    if (child->state == State::kRunning) end(*child);
  if (node.state == State::kComplete) return;  // a child's end propagated to this element
  if (node.state != State::kRunning && node.state != State::kStandby) return;
  if (node.action) node.action->set_running(false);
  const bool repeats = node.type == ElementType::kManeuverGroup || node.type == ElementType::kEvent;
  if (repeats && !(node.max_executions != -1 && node.executions >= node.max_executions)) {
    if (node.start_trigger) node.start_trigger->reset();
    if (node.stop_trigger) node.stop_trigger->reset();
    set_state(node, State::kStandby, StateTransition::kEnd);
    for (Node* child : node.children) reset(*child);
  } else {
    set_state(node, State::kComplete, StateTransition::kEnd);
  }
  if (node.parent != nullptr) propagate(*node.parent);
}

void StoryboardRuntime::stop(Node& node) {
  for (Node* child : node.children) stop(*child);
  if (node.state == State::kInit || node.state == State::kComplete) return;
  if (node.action) node.action->set_running(false);
  set_state(node, State::kComplete, StateTransition::kStop);
  if (node.parent != nullptr) propagate(*node.parent);
}

void StoryboardRuntime::eval_triggers(Node& node, double time_s) {
  if (node.state == State::kRunning && node.stop_trigger && node.stop_trigger->evaluate(world_, time_s)) stop(node);
  if (node.state == State::kStandby && (!node.start_trigger || node.start_trigger->evaluate(world_, time_s)))
    start(node, time_s);
  if (node.state == State::kRunning)
    for (Node* child : node.children) eval_triggers(*child, time_s);
}

void StoryboardRuntime::step(Node& node, double time_s, double dt_s) {
  if (node.state != State::kRunning) return;
  if (node.action) {
    if (node.action->running() && node.action->step(world_, time_s, dt_s)) end(node);
    return;
  }
  for (Node* child : node.children) step(*child, time_s, dt_s);
}

bool StoryboardRuntime::step(double time_s, double dt_s) {
  eval_triggers(*root_, time_s);
  for (auto& action : init_)
    if (action->running() && action->step(world_, time_s, dt_s)) action->set_running(false);
  step(*root_, time_s, dt_s);
  return root_->state == State::kRunning;
}

}  // namespace emrm::openscenario::detail
