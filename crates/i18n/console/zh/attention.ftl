# 患者列表中的提醒：各类提醒的名称、紧急程度、每条提醒的句子（由中心发送其标识和参数）以及诊所的提醒阈值。

attention-severity-urgent = 紧急
attention-severity-warning = 今日查看
attention-severity-notice = 留意
attention-severity-label = { $severity }：

## 提醒类型（筛选）

attention-kind-pain-high = 疼痛
attention-kind-pain-rising = 疼痛加重
attention-kind-station-revoked = 训练站已撤销
attention-kind-no-session = 没有训练
attention-kind-decline = 变差
attention-kind-safety-stop = 安全停止
attention-kind-ended-early = 提前结束
attention-kind-effort = 用力程度高
attention-kind-low-activity = 训练量少
attention-kind-wheel-unplugged = 方向盘已断开
attention-kind-sensor-unplugged = 手臂传感器已断开
attention-kind-wheel-unseen = 未检测到方向盘
attention-kind-sensors-lost = 手臂传感器丢失
attention-kind-station-silent = 训练站无响应
attention-kind-torque-at-ceiling = 扭矩达到上限

## 提醒

attention-pain-high = { $at } 的训练后疼痛 { $pain_0_10 }/10{ $sessions_since ->
        [0] {""}
       *[other] （此后 { $sessions_since } 次训练没有疼痛回答）
    }
attention-pain-rising = 疼痛加重：{ $first_0_10 }，然后 { $middle_0_10 }，然后 { $at } 的训练后 { $pain_0_10 }/10
attention-station-revoked = 训练站已于 { $at } 撤销：配对新的训练站前患者无法训练
attention-no-session-yet = 还没有训练（{ $at } 添加）
attention-no-session = 已 { $days } 天没有训练（上次：{ $at }）
attention-decline = { $exercise_kind }训练中{ $measure }变差：{ $latest }，之前为 { $usual }（差 { $worse_percent } %）
attention-safety-stop = { $at } 的训练中发生安全停止
attention-ended-early = 最近 { $sessions } 次训练中有 { $ended_early } 次提前结束
attention-effort-high = { $at } 的训练后用力程度 { $effort_0_10 }/10（Borg CR10）
attention-effort-too-hard = 最近 { $too_hard_sessions } 次训练后均回答“太难”
attention-low-sessions = 本周完成处方 { $sessions_prescribed } 次训练中的 { $sessions } 次
attention-low-minutes = 本周完成处方活动 { $minutes_prescribed } 分钟中的 { $active_minutes } 分钟
attention-low-unprescribed = 本周活动 { $active_minutes } 分钟；尚未开具处方（诊所要求至少 { $minimum_minutes } 分钟）
attention-wheel-unplugged = { $at } 的训练：{ $end }
attention-sensor-unplugged = { $at } 的训练：{ $end }
attention-wheel-unseen = 训练站开机期间已 { $days } 天未检测到方向盘
attention-sensors-lost = 最近 { $sessions } 次训练中手臂传感器丢失
attention-station-silent = 训练站已 { $days } 天没有联系（上次：{ $at }）
attention-torque-at-ceiling = { $at } 的训练中有 { $percent } % 或更多时间扭矩保持在上限

## 诊所的提醒阈值（#/attention-settings）

attention-settings-title = 提醒阈值
attention-settings-intro = 患者列表何时提示患者需要关注。
attention-settings-admin = 更改会立即适用于诊所的所有治疗师，并记入审计日志。
attention-settings-not-admin = 管理员可以更改这些阈值。
attention-settings-save = 保存阈值
attention-settings-saved = 已保存。
attention-settings-out-of-range = 有一个值超出范围（范围见旁边）。
attention-setting-range = （{ $min }–{ $max }；默认 { $default }）
attention-setting-changed = 由 { $who } 于 { $at } 更改。
attention-setting-default = 诊所未更改：默认值。
attention-setting-pain-threshold-0-10 = 紧急疼痛，0–10（达到或超过）
    .why = 0–10 分量表上 7 分或以上为重度疼痛；报告此程度疼痛的患者不应在未联系诊所的情况下继续训练。
attention-setting-pain-rise-points = 疼痛加重：三次回答中上升的分数
    .why = 两分大约是患者能真实感受到的最小疼痛变化。
attention-setting-no-session-days = 没有训练的天数
    .why = 三天不训练会打乱居家训练的节奏；每周处方次数较少时按相应间隔计算（每周一次则为 7 天）。
attention-setting-min-active-minutes-week = 未开处方时每周活动分钟数（至少）
    .why = 每周半小时远低于患者在家能达到的水平（平均每周约 2 小时）；低于此值说明训练站几乎没有使用。
attention-setting-decline-percent = 变差：低于同类早期训练的百分比
    .why = 运动指标在各次训练之间的波动可达约 10 %；15 % 超出了这一波动。
attention-setting-ended-early-sessions = 最近 5 次训练中提前结束的次数
    .why = 一次可能是接了个电话；五次中有两次就值得询问。
attention-setting-effort-threshold-0-10 = 需要查看的用力程度，Borg CR10 0–10（达到或超过）
    .why = 觉得训练吃力的患者容易放弃居家训练；10 分中的 7 分已远超“吃力”。
attention-setting-devices-unseen-days = 训练站开机但没有方向盘的天数
    .why = 方向盘缺失三天通常是线缆或电源问题，而不是患者的选择。
attention-setting-station-silent-days = 训练站可以无响应的天数
    .why = 用于训练的训练站每次训练都会连接；三天无响应说明它已关机、断电或离线。
