# 进行中训练的实时视图。

live-waiting = 等待训练开始…
live-arm-heading = 手臂和方向盘
live-arm-canvas = 患者手臂和方向盘的三维视图；拖动或使用方向键旋转
live-tracking = 跟踪
live-torque-heading = 力矩和辅助
live-joints-heading = 关节角度
live-scene-road = 车辆周围的道路和车道
live-scene-dial = 转盘：目标和方向盘
live-scene-strength = 力量测试：左右两侧
live-tracking-road = 横向偏差
live-tracking-dial = 转盘目标和方向盘角度
live-tracking-strength = 力量：推力与上限
live-axis-time = 训练时间（秒）
live-axis-deviation = 偏差（米）
live-axis-angle = 角度（°）
live-axis-torque = 力矩（N·m）
live-series-deviation = 横向偏差（米）
live-series-wheel = 方向盘角度（°）
live-series-target = 目标（°）
live-series-push = 当前推力（N·m）
live-series-peak = 本侧最大推力（N·m）
live-series-ceiling = 上限（N·m）
live-series-motor = 电机（N·m）
live-series-assist = 辅助（N·m）
live-series-shoulder = 肩关节上抬（°）
live-series-elbow = 肘关节屈曲（°）

live-just-now = 刚刚
live-status-session = { $when } 的训练
live-status-seconds = { $seconds } 秒
live-state-running = 进行中
live-state-paused = 已暂停
live-state-fault = 安全故障：力矩正逐渐降为零
live-status-torque = 力矩 { $nm }，上限 { $ceiling } N·m
live-status-lane = 车道内 { $pct }%
live-status-push = 推力 { $nm } N·m
live-status-dial-off = 偏离转盘目标 { $degrees }°
live-status-delay = 延迟 { $seconds } 秒
live-recording-stopped = 记录已于 { $seconds } 秒停止
live-no-arm-sensors = 本次训练未使用手臂传感器。
live-angles = 肩关节上抬 { $shoulder }°，肘关节屈曲 { $elbow }°，前臂旋前 { $forearm }°
live-delayed-silent = 延迟：已有 { $seconds } 秒未收到工作站的数据（其家庭网络可能已断开）；视图显示的是最后收到的数据
live-delayed-late = 延迟：这些数据晚到了 { $seconds } 秒（工作站在连接中断后正在补发）
live-lagged = 视图落后，跳过了 { $count } 条摘要。
live-stopped-login-ended = 实时视图已停止：您的登录已结束。请重新登录后查看。
live-stopped-login-unchecked = 实时视图已停止：集线器现在无法核对您的登录。请稍后再试。
live-stopped-not-your-patient = 实时视图已停止：该患者已不在您的照护之下。
live-ended-unknown = 已结束（未记录结束方式）
live-ended-complete = 已结束：按处方完成
live-path-note = 车辆最近 { $seconds } 秒的轨迹

live-road-not-sent = 此训练站未发送道路：车辆最近 { $seconds } 秒的轨迹
live-road-note = 车道宽 { $lane } 米，车后 { $behind } 米至车前 { $ahead } 米（比例尺 { $bar } 米）；蓝色：车辆轨迹。
live-road-car-side = { $side ->
    [left] 车辆位于车道中心左侧 { $metres } 米。
    [right] 车辆位于车道中心右侧 { $metres } 米。
   *[centre] 车辆位于车道中心。
}
live-path-none = 转盘训练：道路上没有车辆。
live-path-across = { $what }（宽 { $metres } 米）。
live-dial-waiting = 转盘训练：等待方向盘。
live-dial-note = 目标 { $target }°（橙色虚线），患者方向盘 { $wheel }°（蓝色）：{ $side ->
    [left] 在目标左侧 { $off }°。
    [right] 在目标右侧 { $off }°。
   *[on] 正对目标。
}

live-strength-left = 向左推
live-strength-right = 向右推
live-strength-now-label = { $side }（当前）
live-strength-resting = 力量测试：两侧之间休息，或已结束。上限为 { $ceiling }。
live-strength-note = 力量测试，{ $side ->
    [left] 向左推
   *[right] 向右推
}：当前 { $now }{ $share }，目前最大 { $peak }，上限 { $ceiling }（蓝色：当前；橙色标记：最大值；绿线：上限）。
live-strength-share = （上限的 { $pct }%）
live-strength-caption = 力量测试数据
live-strength-col-side = 侧别
live-strength-col-now = 当前推力
live-strength-col-peak = 目前最大
live-strength-col-ceiling = 上限
live-strength-not-yet = 尚无
