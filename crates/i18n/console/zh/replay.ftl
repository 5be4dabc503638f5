# 已保存训练的回放及可回放训练列表。

replay-loading = 正在加载记录…
replay-none-sent = 中心服务器未发送回放
replay-heading = { $when } 的训练回放（{ $exercise }）
replay-unknown-time = 未知时间
replay-receiving = 正在接收记录…
replay-playback = 回放控制
replay-play = 播放
replay-pause = 暂停
replay-position = 位置
replay-speed = 速度
replay-marks-label = 每项训练结束、下一项开始的位置
replay-car-heading = 俯视车辆（光标前 30 秒）
replay-car-canvas = 俯视的车辆轨迹
replay-chart-tracking = 横向偏差和转盘误差
replay-axis-tracking = 偏差（米）/ 误差（°）
replay-series-dial-error = 转盘跟踪误差（°）
replay-chart-torque = 方向盘力矩
replay-series-motor = 电机力矩（N·m）
replay-series-assist = 辅助力矩（N·m）
replay-series-ceiling = 力矩上限（N·m）
replay-mark = { $named ->
    [yes] { $seconds } 秒：训练 { $ended } 结束，接着是训练 { $next }（{ $name }）
   *[no] { $seconds } 秒：训练 { $ended } 结束，接着是训练 { $next }
}
replay-cut-short = 记录在结束前中断
replay-frames = 共 { $frames } 帧，每秒 { $rate } 帧。
replay-stopped = 回放已停止：{ $reason }

replay-list-heading = 回放训练
replay-list-running = 仍在进行中：训练结束后才会收到记录。
replay-list-not-arrived = 记录尚未到达。训练站会在训练结束后、能连上中心服务器时上传。
replay-list-arriving = 记录正在上传：已收到 { $percent }%。全部到达后即可回放。
replay-list-stalled = 记录上传已中断：已收到 { $percent }%，自 { $at } 起没有新数据。工作站下次联网时会发送其余部分。
replay-list-ready = 记录已就绪：点击日期和时间打开。
replay-list-note = 共 { $count } 次训练，其中 { $ready } 次可根据训练站上传的记录回放：手臂、车辆和图表重现当时情形，可播放、暂停和拖动。
replay-list-none = 尚无训练：训练站上传记录后即可回放。
replay-list-caption = 患者的训练，最新的在前
replay-list-col-started = 开始时间
replay-list-col-exercise = 训练
replay-list-col-recording = 记录
