# 处方表单中训练项目的辅助方式。

assist-label = 辅助
assist-mode-station = 训练站的设置（此处不开具）
assist-mode-none = 无：方向盘不提供帮助
assist-mode-resist = 阻力：弹簧和阻尼与运动方向相反（力量训练）
assist-mode-motion = 运动引导：方向盘沿理想路径引导双手
assist-mode-force = 助力：方向盘按患者自身用力的一定比例助力
assist-mode-hybrid = 混合：在一定范围内自由活动，到达边缘时引导回来
assist-mode-assist_as_needed = 按需辅助：患者出错时帮助增加，不出错时逐渐减少
assist-level-guidance = 级别：引导可使用的力矩上限比例
assist-level-effort = 级别：方向盘按患者用力所加的比例
